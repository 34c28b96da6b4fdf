#pragma once
/// Pose VAEs: the β-VAE pose prior (P-VAE, thesis §3.4.2) and the conditional C-VAE (curve
/// get-up seed §3.5), whose decoder turns a latent vector (and condition) into a natural pose.
/// Loss: MSE reconstruction + β·KL(q(z|x) ‖ N(0, I)). The decoder's output is squashed into the
/// joint limits (mid + half·tanh), so every decoded pose respects them.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "podium/base/json.h"
#include "podium/learn/pose_data.h"

namespace podium::learn {

struct VaeConfig {
  int latent_size = 13;                  ///< thesis §3.4.2: 13 (PCA, 85 % variance)
  std::vector<int> hidden = {256, 256};  ///< encoder and decoder, tanh
  double beta = 1e-6;                    ///< KL weight per pose (PoseVae averages the KL over a minibatch); C-VAE seed §3.5
  double learning_rate = 1e-4;           ///< Adam, both seeds
  int batch_size = 128;                  ///< both seeds
  int epochs = 80;                       ///< thesis: 80; C-VAE seed: 100

  /// The thesis P-VAE (§3.4.2: latent 13, 80 epochs, β 1e-5 on the KL summed over a minibatch of
  /// 128, so 1.28e-3 per pose here).
  static VaeConfig pose_vae();
  /// The curve get-up seed's C-VAE (latent 16, 100 epochs).
  static VaeConfig conditional();
  base::Json to_json() const;
  static VaeConfig from_json(const base::Json& json);
};

class PoseVae {
 public:
  /// `lower`/`upper` are the joint limits of each pose entry; condition_size 0 makes a β-VAE.
  PoseVae(const VaeConfig& config, std::vector<double> lower, std::vector<double> upper, std::size_t condition_size,
          std::uint64_t seed);
  ~PoseVae();

  std::size_t pose_size() const;
  std::size_t latent_size() const;
  std::size_t condition_size() const;
  const std::vector<double>& lower() const;
  const std::vector<double>& upper() const;

  /// Called after each epoch (from 0) with its mean loss; returning false ends training there
  /// (a cancelled trial, a caller's progress report).
  using EpochCallback = std::function<bool(int epoch, double mean_loss)>;
  /// Trains for config.epochs; returns the mean loss of each epoch. Conditions are standardised
  /// with the dataset's mean and deviation (kept with the model).
  std::vector<double> train(const PoseDataset& data, const EpochCallback& after_epoch = {});
  /// The encoder's Gaussian q(z | x, c) = N(mean, diag(std²)).
  struct Posterior {
    std::vector<double> mean;  ///< μ(x, c), latent_size()
    std::vector<double> std;   ///< σ(x, c) = exp(½·log σ²), latent_size()
  };
  Posterior posterior(std::span<const double> pose, std::span<const double> condition = {}) const;
  /// The posterior mean μ(x, c), i.e. posterior().mean.
  std::vector<double> encode(std::span<const double> pose, std::span<const double> condition = {}) const;
  std::vector<double> decode(std::span<const double> latent, std::span<const double> condition = {}) const;
  /// Root-mean-square reconstruction error (rad) of decode(encode(x)) over a dataset.
  double reconstruction_rmse(const PoseDataset& data) const;

  void save(const std::filesystem::path& path) const;
  /// Loads save()'s file into a VAE built with the same config and sizes.
  void load(const std::filesystem::path& path);
  /// save()'s file as a new VAE, built with the config, limits and condition size stored in it;
  /// throws base::UserError naming the file when it is missing or not a saved VAE.
  static std::unique_ptr<PoseVae> from_file(const std::filesystem::path& path);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The decoder as an action space (thesis §3.4.2, curve get-up seed §3.4): action = [z, Δq];
/// PD target = clamp(decode(z, c) + Δq, limits).
std::vector<double> pose_action_to_target(const PoseVae& vae, std::span<const double> action,
                                          std::span<const double> condition = {});

}  // namespace podium::learn
