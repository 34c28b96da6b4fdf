#pragma once
/// The sport primitive (sprint seed §3.2 "Learn the sprint posture"): strides cut from motion at
/// successive maxima of the sagittal angle between the thighs and resampled to K frames; Φ1, a
/// β-VAE over strides (learn's PoseVae without a condition), pretrained on reference strides and
/// frozen; a reference N(μ_ref, Σ_ref) moment-matched over n reference strides; and at each
/// completed stride of the character r_primitive = exp(−k·KL(q_Φ(z | stride) ‖ N(μ_ref, Σ_ref))).
/// Φ2, initialised from Φ1 and trained online on the character's strides, gives q in Φ1's place
/// (`online`; off is the ablation). Written by hand: no packaged library does this.
///
/// Our readings, as the proposal gives no formulas:
///  - the cut signal is s = θ_l − θ_r, the thighs' sagittal angles (sprint_rewards.h): a stride is a
///    whole gait cycle (two steps), from one maximum of s (the left thigh furthest ahead) to the
///    next. StrideCutter takes one maximum per excursion of s above +h, known once s falls below
///    −h, so jitter within an excursion makes no extra cut;
///  - a frame of a stride is the pose (character/pose_bridge.h: hinge angles, exponential maps)
///    and the root's rotation in its heading frame as an exponential map (3: the trunk's lean);
///    K frames interpolated linearly in time over the stride;
///  - Σ_ref = Cov(μ_i) + mean(diag σ_i²) over the n posteriors (the moment-matched mixture);
///  - k = ln 2 / the median KL of the held-out reference strides unless set, so a typical
///    reference stride scores 0.5.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/character/pose_bridge.h"
#include "podium/learn/pose_data.h"
#include "podium/learn/vae.h"
#include "podium/sim/model.h"

namespace podium::tasks::sprint {

struct PrimitiveSettings {
  std::vector<std::string> clips;  ///< the reference runs: DeepMimic-format clips in humanoid34's joint layout
  int frames = 16;                 ///< K, frames per stride
  double hysteresis_rad = 0.1;     ///< h of the cut
  double min_stride_s = 0.3;       ///< shorter or longer strides are dropped (a stumble, a stand)
  double max_stride_s = 2.0;
  int latent = 8;              ///< Φ1's latent size
  int epochs = 300;            ///< Φ1's pretraining
  double beta = 1e-3;          ///< Φ1's KL weight (learn's PoseVae: per stride, MSE averaged per entry)
  int reference_strides = 64;  ///< n, drawn with replacement from the training strides
  int holdout_every = 5;       ///< every n-th reference stride is held out (for k)
  double k = 0.0;              ///< the KL's scale; 0: ln 2 / the held-out median
  bool online = true;          ///< Φ2 trained online on the character's strides (false: Φ1 alone)
  int online_epochs = 1;       ///< Φ2's epochs over its buffer per training iteration
  int online_buffer = 256;     ///< the character's latest strides Φ2 trains on
  base::Json to_json() const;
};

/// One maximum of s per excursion above +h, reported once s falls below −h.
class StrideCutter {
 public:
  explicit StrideCutter(double hysteresis_rad) : h_(hysteresis_rad) {}
  void reset();
  /// The sample of index `index` (increasing); the index of a maximum confirmed by it, if any.
  std::optional<std::int64_t> observe(std::int64_t index, double s);
  /// Inside an excursion, the index of its maximum so far (the earliest a next cut can be).
  std::optional<std::int64_t> candidate() const { return above_ ? std::optional(best_index_) : std::nullopt; }
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  double h_;
  bool above_ = false;  // inside an excursion above +h
  double best_ = 0.0;
  std::int64_t best_index_ = 0;
};

/// K frames interpolated linearly over `frames` (each F values, uniform in time), flattened K·F.
std::vector<double> resample_stride(std::span<const std::vector<double>> frames, int k);

/// A stride frame of configuration q: the pose, then the root's rotation in its heading frame (3).
std::vector<double> stride_frame(const character::PoseBridge& bridge, const Eigen::VectorXd& q);
/// s = θ_l − θ_r of configuration q (runs forward kinematics on `scratch`).
double thigh_signal(const sim::CharacterModel& model, sim::CharacterData& scratch, const Eigen::VectorXd& q);

/// Cuts strides from a stream of frames at control rate (the env's and the clips' one rule).
class StrideRecorder {
 public:
  StrideRecorder(const PrimitiveSettings& settings, double dt_s);
  void reset();
  /// The frame of this step and its s; a completed stride (K·F values) when one ends here.
  std::optional<std::vector<double>> observe(std::vector<double> frame, double s);
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  PrimitiveSettings settings_;
  double dt_;
  StrideCutter cutter_;
  std::int64_t index_ = 0;
  std::optional<std::int64_t> last_peak_;
  std::int64_t first_ = 0;  // the index of frames_.front()
  std::vector<std::vector<double>> frames_;
};

/// The strides of clips and of their mirror images (character/motion.h; a looping clip, one
/// cycle, taken three times over) on `model` at `control_hz`, as a dataset for learn's PoseVae (entries named
/// "k<i>/<dof>", limits the joints' and ±π for the root's rotation). Throws base::UserError naming
/// a clip that cannot be read.
learn::PoseDataset strides_from_clips(const sim::ModelPtr& model, double control_hz, const PrimitiveSettings& settings);

/// KL(N(m, diag s²) ‖ N(μ, Σ)), nats.
double gaussian_kl(const Eigen::VectorXd& m, const Eigen::VectorXd& s, const Eigen::VectorXd& mu, const Eigen::MatrixXd& sigma);

class SportPrimitive {
 public:
  /// Pretrains Φ1 on the strides (the held-out ones excepted) and makes the reference and k.
  /// Throws base::UserError for fewer than 2 training strides.
  SportPrimitive(const learn::PoseDataset& strides, const PrimitiveSettings& settings, std::uint64_t seed);
  ~SportPrimitive();

  /// KL of a stride's posterior under the encoder in use (Φ2 when online, else Φ1) to the reference.
  double kl(std::span<const double> stride) const;
  /// r_primitive / w_primitive = exp(−k·KL).
  double reward(std::span<const double> stride) const;
  /// Φ2 (online only): `online_epochs` over the strides. Not while kl() runs on another thread.
  void adapt(const std::vector<std::vector<double>>& strides);

  const PrimitiveSettings& settings() const { return settings_; }
  double k() const { return k_; }
  const Eigen::VectorXd& reference_mean() const { return mu_; }
  const Eigen::MatrixXd& reference_covariance() const { return sigma_; }
  std::size_t stride_size() const;
  /// Figures for the trial's info: strides, k, the held-out and training median KL.
  base::Json summary() const;

  /// Φ2 to a file and back (a checkpoint's part; Φ1 and the reference are remade from the seed).
  void save_online(const std::filesystem::path& file) const;
  void load_online(const std::filesystem::path& file);

 private:
  PrimitiveSettings settings_;
  std::unique_ptr<learn::PoseVae> phi1_, phi2_;
  learn::PoseDataset template_;  // the dataset's names and limits, for Φ2's batches
  Eigen::VectorXd mu_;
  Eigen::MatrixXd sigma_;
  double k_ = 1.0;
  base::Json summary_;
};

}  // namespace podium::tasks::sprint
