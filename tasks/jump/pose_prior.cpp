#include "pose_prior.h"

#include <algorithm>
#include <chrono>

#include "podium/base/error.h"
#include "podium/character/motion.h"
#include "podium/character/pose_bridge.h"

namespace podium::tasks::jump {

namespace fs = std::filesystem;

PosePriorSettings read_pose_prior_settings(base::ConfigReader& r) {
  PosePriorSettings s;
  learn::VaeConfig& v = s.vae;
  s.pose_set = r.path("pose_set", s.pose_set,
                      "P-VAE training poses: empty: the shipped athlete set; a folder of DeepMimic clips; a pose-set .json");
  v.epochs = r.integer<int>("vae_epochs", v.epochs, {.min = 1}, "P-VAE epochs (§3.4.2: 80)");
  v.latent_size = r.integer<int>("vae_latent_size", v.latent_size, {.min = 1}, "P-VAE latent dimension (§3.4.2: 13)");
  v.beta = r.number("vae_beta", v.beta, {.min = 0.0}, "P-VAE KL weight per pose (§3.4.2's 1e-5 × the minibatch of 128)");
  v.learning_rate =
      r.number("vae_learning_rate", v.learning_rate, {.min = 0.0, .exclusive_min = true}, "P-VAE Adam rate (§3.4.2: 1e-4)");
  v.batch_size = r.integer<int>("vae_batch_size", v.batch_size, {.min = 1}, "P-VAE minibatch (§3.4.2: 128)");
  return s;
}

fs::path shipped_pose_set_path() { return fs::path(PODIUM_LEARN_DATA_DIR) / "athlete_poses.json"; }

namespace {

// The β-VAE's poses carry no conditions (those are the C-VAE's), so sets of any source append.
learn::PoseDataset without_conditions(learn::PoseDataset d) {
  d.condition_names.clear();
  d.conditions.clear();
  return d;
}

learn::PoseDataset read_pose_file(const fs::path& file, const character::PoseBridge& bridge) {
  learn::PoseDataset d = without_conditions(learn::read_pose_dataset(file));
  const std::string model = "model " + bridge.model().name();
  if (d.dof_names.size() != bridge.size())
    throw base::UserError("pose set " + file.string() + ": poses of " + std::to_string(d.dof_names.size()) + " DoFs; " + model +
                          " has " + std::to_string(bridge.size()));
  if (d.dof_names != bridge.dof_names())
    throw base::UserError("pose set " + file.string() + ": its dof_names are not " + model + "'s joints in link order");
  return d;
}

learn::PoseDataset read_clip_folder(const fs::path& folder, const character::PoseBridge& bridge, const sim::ModelPtr& model) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file() && entry.path().extension() == ".txt") files.push_back(entry.path());
  if (files.empty()) throw base::UserError("pose_set " + folder.string() + ": no DeepMimic clips (*.txt) in this folder");
  std::sort(files.begin(), files.end());  // the directory's order is the file system's; the set's is fixed
  learn::PoseDataset set;
  set.dof_names = bridge.dof_names();
  set.lower = bridge.lower();
  set.upper = bridge.upper();
  for (const fs::path& file : files) {
    const character::Clip clip = character::read_deepmimic_clip(model, file);
    set.append(without_conditions(character::poses_from_clip(bridge, clip)));
    set.append(without_conditions(character::poses_from_clip(bridge, character::mirror(clip))));
  }
  return set;
}

}  // namespace

learn::PoseDataset read_pose_prior_set(const std::string& pose_set, const sim::ModelPtr& model) {
  const character::PoseBridge bridge(model);  // z-up: see the header
  if (pose_set.empty()) return read_pose_file(shipped_pose_set_path(), bridge);
  const fs::path path(pose_set);
  if (fs::is_directory(path)) return read_clip_folder(path, bridge, model);
  if (fs::is_regular_file(path) && path.extension() == ".json") return read_pose_file(path, bridge);
  throw base::UserError("pose_set " + pose_set + ": " +
                        (fs::exists(path) ? "neither a folder of clips nor a pose-set .json" : "no such folder or file"));
}

PoseVaeOutcome train_pose_prior(const PosePriorSettings& settings, const fs::path& work_dir, std::uint64_t seed,
                                const std::atomic<bool>* cancel, const PosePriorReport& report) {
  const auto start = std::chrono::steady_clock::now();
  const sim::ModelPtr model = sim::load_shipped_model(settings.model);
  const learn::PoseDataset set = read_pose_prior_set(settings.pose_set, model);
  learn::PoseVae vae(settings.vae, set.lower, set.upper, 0, seed);

  PoseVaeOutcome out;
  out.poses = set.size();
  const int epochs = settings.vae.epochs;
  out.epoch_losses = vae.train(set, [&](int epoch, double loss) {
    if (report.metric) report.metric("pose_vae_loss", epoch + 1, loss);
    if (report.progress) report.progress(double(epoch + 1) / epochs);
    return !(cancel && cancel->load());
  });
  out.cancelled = cancel && cancel->load();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (out.cancelled) return out;

  out.rmse_rad = vae.reconstruction_rmse(set);
  if (report.metric) report.metric("pose_vae_rmse_rad", epochs, out.rmse_rad);
  out.file = work_dir / "pose_vae.pt";
  const fs::path partial = work_dir / "pose_vae.pt.partial";
  vae.save(partial);
  fs::rename(partial, out.file);
  return out;
}

PosePrior load_pose_prior(const fs::path& path, character::PoseBridge::Frame frame) {
  return PosePrior{std::shared_ptr<const learn::PoseVae>(learn::PoseVae::from_file(path)), frame};
}

}  // namespace podium::tasks::jump
