#pragma once
/// The sprint's reward terms (sprint seed §2 "Reward", §3.2), each a pure function of a few numbers
/// or of one state. The seed names the terms but gives no formulas beyond r_mirror's; the forms
/// below are ours, with their weights and kernels as preset data (sprint_preset.h):
///   r_f    = w_f · (x_t − x_{t−1}) / Δt, the root's forward speed between control steps (§2);
///   r_s    = the survival bonus while not fallen (§2);
///   r_d    = −w_d · (d / (w/2))², d the root's lateral offset from the lane centre (§2): 0 at the
///            centre, −w_d at the lane's edge;
///   r_mass = −w_m · ‖c − c_up‖, c the COM relative to the root in the heading frame, c_up that of
///            the upright sprint posture (§3.2);
///   r_diag = w_diag · exp(−k_diag · ((θ_lh − θ_rh) − (θ_rs − θ_ls))²) over the thighs' and upper
///            arms' sagittal angles (§3.2 "the motion of legs and arms is diagonal"): 1 when the left
///            thigh leads the right by as much as the right arm leads the left;
///   r_mirror (mirror.h) weighted by w_mirror.
#include <Eigen/Core>

#include "podium/sim/data.h"
#include "podium/sim/model.h"

namespace podium::tasks::sprint {

struct RewardWeights {
  double forward = 1.0;     ///< w_f, per m/s
  double survival = 1.0;    ///< r_s per control step
  double lateral = 1.0;     ///< w_d
  double mass = 1.0;        ///< w_m, per m
  double mirror = 0.5;      ///< w_mirror
  double mirror_k = 1.0;    ///< k of r_mirror, per rad²
  double diagonal = 0.5;    ///< w_diag
  double diagonal_k = 2.0;  ///< k_diag, per rad²
  /// w_primitive of §3.2's r_primitive (primitive.h: a β-VAE sport primitive over strides), given
  /// at each completed stride: the accelerate stage's `primitive_weight`, not the track preset's.
  double primitive = 0.0;
};

/// r_f: the root's forward displacement over the control step's duration, m/s (unweighted).
double forward_speed(double x_before_m, double x_after_m, double dt_s);
/// r_d: −w_d (d / (w/2))² for lateral offset d from the lane centre and lane width w.
double lateral_penalty(double offset_m, double lane_width_m, double weight);

/// r_base = r_f + r_s + r_d (§2), weighted, term by term.
struct BaseReward {
  double forward = 0.0, survival = 0.0, lateral = 0.0;
  double total() const { return forward + survival + lateral; }
};
/// r_base of one control step: the root's x before and after it (Δt apart), its lateral offset from
/// the lane centre, and whether the character has fallen (no survival bonus then).
BaseReward base_reward(const RewardWeights& weights, double x_before_m, double x_after_m, double dt_s, double lateral_offset_m,
                       double lane_width_m, bool fallen);

/// The COM relative to the root, in the root's heading frame (character/frames.h), m; runs
/// forward kinematics on `data` (its q).
Eigen::Vector3d com_in_heading_frame(const sim::CharacterModel& model, sim::CharacterData& data);
/// r_mass: −w_m ‖c − c_up‖.
double mass_penalty(const Eigen::Vector3d& com_heading, const Eigen::Vector3d& upright_com_heading, double weight);

/// The sagittal angle of a limb segment, rad: its rest direction (down, −z at q = 0, as every limb
/// of humanoid34 hangs) in the root's heading frame, atan2(forward, down); positive when swung forward.
/// Needs forward kinematics on `data`.
double sagittal_angle(const sim::CharacterModel& model, const sim::CharacterData& data, int body);

/// The four swing angles r_diag compares, rad.
struct SwingAngles {
  double left_hip = 0, right_hip = 0, left_shoulder = 0, right_shoulder = 0;
};
/// r_diag / w_diag = exp(−k ((θ_lh − θ_rh) − (θ_rs − θ_ls))²).
double diagonal_reward(const SwingAngles& swing, double k);

}  // namespace podium::tasks::sprint
