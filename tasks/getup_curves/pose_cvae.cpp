#include "pose_cvae.h"

#include <Eigen/Core>
#include <Eigen/SVD>
#include <cmath>

#include "curve_extraction.h"
#include "podium/base/error.h"
#include "podium/character/motion.h"
#include "podium/character/pose_bridge.h"

namespace podium::tasks::getup_curves {

namespace fs = std::filesystem;

PoseCvaeSettings read_pose_cvae_settings(base::ConfigReader& r) {
  PoseCvaeSettings s;
  s.clips = r.objects(
      "pose_clips",
      [](base::ConfigReader& c) {
        PoseClip p;
        p.clip = c.file("clip", base::required, "a DeepMimic-format clip in the humanoid3d joint layout");
        p.character = c.file("character", base::required, "the DeepMimic character file of the skeleton it was captured on");
        return p;
      },
      "pose_cvae: the C-VAE's training clips (e.g. ../shared/data's seven get-up clips, tasks/getup_curves/README.md)");
  learn::VaeConfig& v = s.vae;
  v.epochs = r.integer<int>("cvae_epochs", v.epochs, {.min = 1}, "C-VAE epochs (§3.5: 100)");
  v.latent_size = r.integer<int>("cvae_latent_size", v.latent_size, {.min = 1, .max = 256}, "C-VAE latent dimension (§3.5: 16)");
  v.beta = r.number("cvae_beta", v.beta, {.min = 0.0}, "C-VAE KL weight (§3.5: 1e-6)");
  v.batch_size = r.integer<int>("cvae_batch_size", v.batch_size, {.min = 1}, "C-VAE minibatch (§3.5: 128)");
  s.holdout_every = r.integer<int>("cvae_holdout_every", s.holdout_every, {.min = 2},
                                   "every n-th frame is held out of training to measure reconstruction (ours)");
  s.conditional = r.boolean("cvae_conditional", s.conditional,
                            "true: the C-VAE of §3.5, conditioned on each pose's (h, θ_x, θ_z); false: §6.4's ablation, an "
                            "unconditional pose VAE on the same poses");
  return s;
}

CvaePoses read_cvae_poses(const std::vector<PoseClip>& clips, const sim::ModelPtr& model, int holdout_every) {
  if (clips.empty()) throw base::UserError("pose_cvae: no pose_clips");
  const character::PoseBridge bridge(model);
  const double neck = standing_neck_height(*model);
  CvaePoses out;
  for (learn::PoseDataset* d : {&out.train, &out.heldout}) {
    d->dof_names = bridge.dof_names();
    d->lower = bridge.lower();
    d->upper = bridge.upper();
    d->condition_names = {"h_m", "theta_x_rad", "theta_z_rad"};
  }
  for (const PoseClip& c : clips) {
    for (const std::string& f : {c.clip, c.character})
      if (!fs::is_regular_file(f)) throw base::UserError("pose_cvae: " + f + " is not a file");
    const sim::ModelPtr own = sim::load_deepmimic(c.character);
    const character::Clip on_own = character::read_deepmimic_clip(own, c.clip);
    const FeatureTrack track = feature_track(on_own, neck / standing_neck_height(*own));  // h carried to `model`
    const learn::PoseDataset poses = character::poses_from_clip(bridge, character::read_deepmimic_clip(model, c.clip));
    if (poses.size() != track.features.size())
      throw base::UserError("pose_cvae: " + c.clip + ": " + std::to_string(poses.size()) + " poses on " + model->name() +
                            " but " + std::to_string(track.features.size()) + " frames on " + c.character);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      learn::PoseDataset& d = (k + 1) % static_cast<std::size_t>(holdout_every) == 0 ? out.heldout : out.train;
      d.poses.push_back(poses.poses[k]);
      const StyleFeatures& w = track.features[k];
      d.conditions.push_back({w(0), w(1), w(2)});
    }
  }
  return out;
}

namespace {

Eigen::MatrixXd pose_matrix(const learn::PoseDataset& d) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(d.size()), static_cast<Eigen::Index>(d.dof_names.size()));
  for (std::size_t i = 0; i < d.size(); ++i)
    for (std::size_t j = 0; j < d.poses[i].size(); ++j)
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d.poses[i][j];
  return m;
}

}  // namespace

int principal_components_for(const learn::PoseDataset& poses, double fraction) {
  Eigen::MatrixXd m = pose_matrix(poses);
  m.rowwise() -= m.colwise().mean();
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues();
  const Eigen::VectorXd variance = s.array().square();
  const double total = variance.sum();
  double covered = 0.0;
  for (Eigen::Index k = 0; k < variance.size(); ++k) {
    covered += variance(k);
    if (covered >= fraction * total) return static_cast<int>(k + 1);
  }
  return static_cast<int>(variance.size());
}

double mean_pose_rmse(const learn::PoseDataset& train, const learn::PoseDataset& data) {
  const Eigen::RowVectorXd mean = pose_matrix(train).colwise().mean();
  Eigen::MatrixXd m = pose_matrix(data);
  m.rowwise() -= mean;
  return std::sqrt(m.squaredNorm() / static_cast<double>(m.size()));
}

base::Json PoseCvaeOutcome::to_json() const {
  return {{"train_poses", train_poses},
          {"heldout_poses", heldout_poses},
          {"train_rmse_rad", train_rmse_rad},
          {"heldout_rmse_rad", heldout_rmse_rad},
          {"mean_pose_rmse_rad", mean_pose_rmse_rad},
          {"pca_components_85", pca_components_85}};
}

PoseCvaeOutcome train_pose_cvae(const PoseCvaeSettings& settings, const fs::path& work_dir, std::uint64_t seed,
                                const std::atomic<bool>* cancel,
                                const std::function<void(const std::string&, double, double)>& metric,
                                const std::function<void(double)>& progress) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  CvaePoses poses = read_cvae_poses(settings.clips, model, settings.holdout_every);
  if (!settings.conditional)  // §6.4's ablation: the same poses without their labels
    for (learn::PoseDataset* d : {&poses.train, &poses.heldout}) d->condition_names.clear(), d->conditions.clear();
  learn::PoseVae vae(settings.vae, poses.train.lower, poses.train.upper, poses.train.condition_names.size(), seed);
  PoseCvaeOutcome out;
  out.train_poses = poses.train.size();
  out.heldout_poses = poses.heldout.size();
  const int epochs = settings.vae.epochs;
  vae.train(poses.train, [&](int epoch, double loss) {
    if (metric) metric("pose_cvae_loss", epoch + 1, loss);
    if (progress) progress(static_cast<double>(epoch + 1) / epochs);
    return !(cancel && cancel->load());
  });
  out.cancelled = cancel && cancel->load();
  if (out.cancelled) return out;
  out.train_rmse_rad = vae.reconstruction_rmse(poses.train);
  out.heldout_rmse_rad = poses.heldout.size() > 0 ? vae.reconstruction_rmse(poses.heldout) : 0.0;
  out.mean_pose_rmse_rad = poses.heldout.size() > 0 ? mean_pose_rmse(poses.train, poses.heldout) : 0.0;
  out.pca_components_85 = principal_components_for(poses.train, 0.85);
  if (metric) {
    metric("pose_cvae_rmse_rad", epochs, out.train_rmse_rad);
    metric("pose_cvae_heldout_rmse_rad", epochs, out.heldout_rmse_rad);
    metric("pose_cvae_mean_pose_rmse_rad", epochs, out.mean_pose_rmse_rad);
  }
  out.file = work_dir / "pose_cvae.pt";
  const fs::path partial = work_dir / "pose_cvae.pt.partial";
  vae.save(partial);
  fs::rename(partial, out.file);
  return out;
}

}  // namespace podium::tasks::getup_curves
