#pragma once
/// The pose C-VAE of the curve get-up seed (§3.5): a conditional VAE over humanoid34's joint poses
/// (learn::PoseVae; encoder and decoder 2×256 tanh, latent 16, β = 1e-6, Adam 1e-4, 100 epochs,
/// batch 128: learn::VaeConfig::conditional()) whose condition c is the pose's style features
/// w = (h, θ_x, θ_z) (style_features.h; m and rad), computed once per frame by forward kinematics.
/// The policy then acts through its decoder: q̄ = DECODER(z, c) + Δq with c = the curves' targets
/// now (curve_env.h, actions "cvae").
///
/// Poses come from DeepMimic-format clips in the humanoid3d joint layout (the get-up clips of
/// ../shared/data: DeepMimic's getup_faceup/facedown, CMU 139_16, 139_17, 140_01–03): each clip
/// is read onto humanoid34 for its poses (the layouts match joint for joint), and onto its own
/// skeleton for its features, whose heights are carried to humanoid34 by the ratio of the two
/// standing neck heights (curve_extraction.h). Ours, not the seed's: every 10th frame is held out
/// to measure reconstruction on poses the C-VAE did not train on, and no mirrored copies are added.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "podium/learn/pose_data.h"
#include "podium/learn/vae.h"
#include "podium/sim/model.h"

namespace podium::tasks::getup_curves {

/// One training clip and the skeleton it was captured on (DeepMimic character file).
struct PoseClip {
  std::string clip, character;
};

struct PoseCvaeSettings {
  std::vector<PoseClip> clips;
  learn::VaeConfig vae = learn::VaeConfig::conditional();
  int holdout_every = 10;  ///< every n-th frame (n − 1, 2n − 1, ...) is held out; ours
  /// false: §6.4's ablation, an unconditional pose VAE (a β-VAE on the same poses, no labels);
  /// the train stage's "cvae" actions then decode without the curves' targets.
  bool conditional = true;
};

/// Reads pose_clips and the cvae_* keys; errors name the JSON path and the value.
PoseCvaeSettings read_pose_cvae_settings(base::ConfigReader& r);

/// The clips' poses on `model` (humanoid34) labelled by their style features (condition_names
/// h_m, theta_x_rad, theta_z_rad), split into training and held-out frames. Throws
/// base::UserError naming a clip that is missing or does not fit the model.
struct CvaePoses {
  learn::PoseDataset train, heldout;
};
CvaePoses read_cvae_poses(const std::vector<PoseClip>& clips, const sim::ModelPtr& model, int holdout_every);

/// The smallest number of principal components of the poses covering `fraction` of their variance
/// (§3.5's check: 16 on LAFAN1 for 85%).
int principal_components_for(const learn::PoseDataset& poses, double fraction);

/// RMS (rad) over `data` of the training set's mean pose against each pose: the baseline a
/// C-VAE's reconstruction must beat.
double mean_pose_rmse(const learn::PoseDataset& train, const learn::PoseDataset& data);

struct PoseCvaeOutcome {
  std::filesystem::path file;  ///< work_dir/pose_cvae.pt; empty when cancelled
  std::size_t train_poses = 0, heldout_poses = 0;
  double train_rmse_rad = 0.0, heldout_rmse_rad = 0.0;  ///< decode(encode(x, c), c) − x
  double mean_pose_rmse_rad = 0.0;                      ///< the training mean pose on the held-out frames
  int pca_components_85 = 0;                            ///< §3.5's check on the training poses
  bool cancelled = false;
  base::Json to_json() const;
};

/// Reads the poses, trains the C-VAE with `seed` (checking `cancel` after every epoch; metric
/// "pose_cvae_loss" per epoch) and saves it whole to work_dir/pose_cvae.pt.
PoseCvaeOutcome train_pose_cvae(const PoseCvaeSettings& settings, const std::filesystem::path& work_dir, std::uint64_t seed,
                                const std::atomic<bool>* cancel,
                                const std::function<void(const std::string&, double, double)>& metric,
                                const std::function<void(double)>& progress);

}  // namespace podium::tasks::getup_curves
