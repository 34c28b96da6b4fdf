// Times the jump task's P-VAE training (thesis §3.4.2 settings, one CPU thread) and reports its
// reconstruction error on the training poses and on a held-out tenth, which a model that only
// memorised the set would miss. The held-out run trains a second VAE on the other nine tenths.
// It also says where the latent code lies: the encodings' mean and spread per dimension, and how
// far decode(0), the pose of a zero latent action, is from the nearest training pose.
// Usage: jump_pose_prior_bench [POSE_SET] [EPOCHS] [LEARNING_RATE] [BETA]
// e.g. jump_pose_prior_bench "" 80          (the shipped athlete set)
//      jump_pose_prior_bench ../shared/data/jump/data/vae/txt 80
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_args.h"
#include "pose_prior.h"

using namespace podium;
using namespace podium::tasks::jump;

int main(int argc, char** argv) {
  PosePriorSettings s;
  if (argc > 5 || (argc > 2 && !bench::count(argv[2], 1, 1'000'000, s.vae.epochs)) ||
      (argc > 3 && !(bench::real_number(argv[3], s.vae.learning_rate) && s.vae.learning_rate > 0)) ||
      (argc > 4 && !(bench::real_number(argv[4], s.vae.beta) && s.vae.beta >= 0))) {
    std::fprintf(stderr, "usage: %s [POSE_SET] [EPOCHS ≥ 1] [LEARNING_RATE > 0] [BETA ≥ 0]\n", argv[0]);
    return 2;
  }
  if (argc > 1) s.pose_set = argv[1];
  const auto dir = std::filesystem::temp_directory_path() / "jump_pose_prior_bench";
  std::filesystem::create_directories(dir);

  const PoseVaeOutcome out = train_pose_prior(s, dir, 1);
  std::printf("pose set %s: %zu poses, %d epochs, lr %g, beta %g: %.1f s (reading included)\n",
              s.pose_set.empty() ? "(shipped)" : s.pose_set.c_str(), out.poses, s.vae.epochs, s.vae.learning_rate, s.vae.beta,
              out.seconds);
  std::printf("loss first epoch %.5f, last %.5f; reconstruction RMSE on the training set %.4f rad\n", out.epoch_losses.front(),
              out.epoch_losses.back(), out.rmse_rad);

  // Held-out error: every tenth pose left out of training.
  learn::PoseDataset all = read_pose_prior_set(s.pose_set, sim::load_shipped_model(s.model)), train = all, held = all;
  train.poses.clear();
  held.poses.clear();
  for (std::size_t i = 0; i < all.size(); ++i) (i % 10 == 9 ? held : train).poses.push_back(all.poses[i]);
  learn::PoseVae vae(s.vae, all.lower, all.upper, 0, 1);
  vae.train(train);
  std::printf("held-out tenth: RMSE %.4f rad (training nine tenths %.4f rad)\n", vae.reconstruction_rmse(held),
              vae.reconstruction_rmse(train));
  // For scale: the error of answering every pose with the set's mean pose.
  std::vector<double> mean(all.dof_names.size(), 0.0);
  for (const auto& p : all.poses)
    for (std::size_t k = 0; k < p.size(); ++k) mean[k] += p[k] / double(all.size());
  double sq = 0.0;
  for (const auto& p : all.poses)
    for (std::size_t k = 0; k < p.size(); ++k) sq += (p[k] - mean[k]) * (p[k] - mean[k]);
  std::printf("mean pose as the answer: RMSE %.4f rad\n", std::sqrt(sq / double(all.size() * mean.size())));
  const PosePrior prior = load_pose_prior(out.file);
  const std::size_t nz = prior.vae->latent_size();
  std::vector<double> z_mean(nz, 0.0), z_sq(nz, 0.0);
  for (const auto& p : all.poses) {
    const std::vector<double> z = prior.vae->encode(p);
    for (std::size_t k = 0; k < nz; ++k) {
      z_mean[k] += z[k] / double(all.size());
      z_sq[k] += z[k] * z[k] / double(all.size());
    }
  }
  std::printf("encodings per latent dimension, mean ± std:");
  for (std::size_t k = 0; k < nz; ++k)
    std::printf(" %.2f±%.2f", z_mean[k], std::sqrt(std::max(0.0, z_sq[k] - z_mean[k] * z_mean[k])));
  const std::vector<double> zero = prior.vae->decode(std::vector<double>(nz, 0.0));
  double nearest = 1e9, to_mean = 0.0;
  for (const auto& p : all.poses) {
    double d = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) d += (p[k] - zero[k]) * (p[k] - zero[k]);
    nearest = std::min(nearest, std::sqrt(d / double(p.size())));
  }
  for (std::size_t k = 0; k < mean.size(); ++k) to_mean += (zero[k] - mean[k]) * (zero[k] - mean[k]);
  std::printf("\ndecode(0): RMS %.4f rad from the nearest training pose, %.4f rad from the mean pose\n", nearest,
              std::sqrt(to_mean / double(mean.size())));
  std::printf("saved to %s (%.0f kB), loads with %zu latent dims\n", out.file.c_str(),
              double(std::filesystem::file_size(out.file)) / 1024.0, prior.vae->latent_size());
  return 0;
}
