#pragma once
/// The jump task's pose prior (thesis §3.4.2): a β-VAE over the athlete's joint
/// poses whose decoder turns the policy's latent action into a natural PD target pose. It trains
/// on the project's authored pose set (learn/data/athlete_poses.json, made by
/// make_athlete_poses.py) unless the user points to DeepMimic-format clips of the same skeleton,
/// such as the CMU clips of arpspoof/Jump's data/vae/txt, which the thesis's authors used.
///
/// Poses are in z-up joint frames (character::PoseBridge's default) whatever their source:
/// read_deepmimic_clip turns clips z-up on reading, so every set shares one layout and the prior's
/// frame is always z_up.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "jump_env.h"
#include "podium/base/config.h"
#include "podium/learn/pose_data.h"
#include "podium/learn/vae.h"
#include "podium/sim/model.h"

namespace podium::tasks::jump {

struct PosePriorSettings {
  /// "" : the shipped set (shipped_pose_set_path()); a folder: every *.txt below it (recursively)
  /// as a DeepMimic-format clip of `model`; a .json file: a pose set in learn's format.
  std::string pose_set;
  /// The skeleton the poses are for: JumpSettings::model (not a config key of its own).
  std::string model = "athlete";
  /// learn::VaeConfig::pose_vae(), the thesis's (§3.4.2: 2 × 256 tanh, d_latent 13, Adam 1e-4,
  /// minibatch 128, 80 epochs, β 1e-5). That β (kl_coeff = 0.00001 in the authors' arpspoof/Jump
  /// utils/vae.py) weighs the KL *summed* over the minibatch against the per-entry mean squared
  /// error; PoseVae averages the KL, so the same loss has β = 1.28e-3 per pose. It matters: with
  /// 1e-5 per pose the encodings drift off the origin (means up to ±0.8 on the shipped set) and
  /// decode(0), the policy's zero latent action, is no training pose.
  learn::VaeConfig vae = learn::VaeConfig::pose_vae();
};

/// Reads pose_set, vae_epochs, vae_latent_size, vae_beta, vae_learning_rate and vae_batch_size
/// (all optional) for a plugin's config; errors name the key.
PosePriorSettings read_pose_prior_settings(base::ConfigReader& r);

/// learn/data/athlete_poses.json in the source tree.
std::filesystem::path shipped_pose_set_path();

/// The training poses for `model` (see PosePriorSettings::pose_set). Clips contribute every frame
/// and its mirror image (left ↔ right, as the authors' train_pose_vae.py does); their hinge values
/// are clamped into the limits. Throws base::UserError naming the folder or file that is missing,
/// holds no clips, or does not fit the model's joints.
learn::PoseDataset read_pose_prior_set(const std::string& pose_set, const sim::ModelPtr& model);

/// Where training reports; either may be empty.
struct PosePriorReport {
  std::function<void(double fraction)> progress;
  /// "pose_vae_loss" per epoch (step = epoch, from 1), then "pose_vae_rmse_rad" at the last epoch.
  std::function<void(const std::string& name, double step, double value)> metric;
};

struct PoseVaeOutcome {
  std::filesystem::path file;        ///< work_dir/pose_vae.pt; empty when cancelled
  std::size_t poses = 0;             ///< the training set's size
  std::vector<double> epoch_losses;  ///< mean loss per epoch (MSE + β·KL)
  double rmse_rad = 0.0;             ///< RMS of decode(encode(x)) − x over the training set, rad
  double seconds = 0.0;              ///< reading the set and training
  bool cancelled = false;
};

/// Reads the set, trains a PoseVae on one CPU thread with `seed`, checking `cancel` after every
/// epoch, and saves it to work_dir/pose_vae.pt (written whole, then renamed into place, so a killed
/// attempt never leaves half a file).
PoseVaeOutcome train_pose_prior(const PosePriorSettings& settings, const std::filesystem::path& work_dir, std::uint64_t seed,
                                const std::atomic<bool>* cancel = nullptr, const PosePriorReport& report = {});

/// A saved VAE (train_pose_prior's file) as JumpEnv's prior; `frame` as it was trained (z_up for
/// train_pose_prior's). Throws base::UserError naming a missing or unreadable file.
PosePrior load_pose_prior(const std::filesystem::path& path,
                          character::PoseBridge::Frame frame = character::PoseBridge::Frame::z_up);

}  // namespace podium::tasks::jump
