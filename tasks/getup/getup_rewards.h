#pragma once
/// The get-up rewards of the get-up seed (001, appendix B) as pure functions of a few state
/// numbers, each term a character::tolerance f(i, b, m, v) with App. B's bounds, margin and value.
/// The sigmoids follow the seed repository where App. B's "Gaussian" cannot work: r_h is
/// long-tailed (a Gaussian leaves a lying character no signal), r_straight linear and r_feet
/// quadratic (value 0 at the margin) [Tassa et al. 2020's dm_control `tolerance`].
///
/// Head height: the seed's bound 1.55 m (eq. 5) is above humanoid21's standing head origin
/// (1.472 m), so r_h could never reach 1 on our model if measured there. We measure at the top of
/// the head (origin + the head sphere's radius, 1.562 m standing): a person's height is read at
/// the top of the head, the seed's character is "roughly 1.5 m tall" (App. D), and no invented
/// scale factor is needed. Every head height of this task (r_h, success, metrics) is the head top.
#include <Eigen/Core>

#include "podium/character/character_env.h"

namespace podium::tasks::getup {

/// What R_weak reads (seed §7, App. B.1).
struct WeakState {
  double head_height_m = 0.0;                                 ///< head top above the ground
  double com_height_m = 0.0;                                  ///< h_com
  Eigen::Vector2d com_velocity_xy = Eigen::Vector2d::Zero();  ///< v_com^xy, world, m/s
  double torso_up_z = 0.0;                                    ///< z_torso^up, vertical component of the torso's up axis
  double feet_distance_m = 0.0;                               ///< d_feet, feet distance projected on the ground plane
};

double r_head(double head_height_m);                        ///< eq. 5
double r_straight(double torso_up_z, double com_height_m);  ///< eq. 6
/// eq. 7 with bounds ±`bound` (App. B.3's standing variant: bound 0).
double r_vcom(const Eigen::Vector2d& com_velocity_xy, double bound = 0.3);
double r_feet(double feet_distance_m);  ///< eq. 8
/// eq. 2: R_weak = r_h · r_straight · r_vcom · r_feet.
double reward_weak(const WeakState& s);

/// What R_slow reads (§7 "Slow Get-up Motions", App. B.2): differences to the reference τ_slow.
struct SlowState {
  double com_height_error_m = 0.0;                               ///< Δh_com = h_com − h'_com
  Eigen::Vector3d torso_up_error = Eigen::Vector3d::Zero();      ///< Δo = o_torso − o'_torso
  Eigen::Vector2d hip_velocity_error = Eigen::Vector2d::Zero();  ///< v_hip − v'_hip (both hips' y joints), rad/s
};

double r_com(double com_height_error_m);                  ///< eq. 9
double r_ori(const Eigen::Vector3d& torso_up_error);      ///< eq. 10
double r_hip(const Eigen::Vector2d& hip_velocity_error);  ///< eq. 11 (its second "b" is v)
/// eq. 3: R_slow = r_com · r_ori · (r_hip + 2)/3.
double reward_slow(const SlowState& s);

/// What R_balance reads (App. B.3).
struct BalanceState {
  Eigen::Vector2d com_velocity_xy = Eigen::Vector2d::Zero();
  double torso_up_z = 0.0;
  double com_height_m = 0.0;
  double com_height_error_m = 0.0;  ///< to the standing pose's h_com
  double pose_squared_error = 0.0;  ///< Σ_j ‖q_j − q̂_j‖² over the free joints, rad²
};

/// eq. 12: r_pose = exp(−¼ Σ ‖q_j − q̂_j‖²).
double r_pose(double pose_squared_error);
/// eq. 4: R_balance = r_vcom(b = [0, 0]) · r_straight · r_com · r_pose.
double reward_balance(const BalanceState& s);

/// Where WeakState's numbers come from on a model, found once.
struct BodyReadings {
  /// The top of the head above its origin: the radius of the head body's sphere geom centred at
  /// the body origin (humanoid21: 0.09 m).
  double head_top_m = 0.0;
  int left_foot = -1, right_foot = -1;  ///< indices into Observation::end_effectors
  /// Throws base::UserError for a model whose head is not such a sphere or that lacks the end
  /// effectors foot_left and foot_right.
  static BodyReadings of(const sim::CharacterModel& model);
};
/// WeakState of the env's current state (its features()).
WeakState weak_state(const character::CharacterEnv& env, const BodyReadings& readings);

}  // namespace podium::tasks::getup
