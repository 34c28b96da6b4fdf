// The sport primitive (sprint seed §3.2 "Learn the sprint posture"): strides, Φ1 and Φ2, the
// reference and r_primitive.
#include "primitive.h"

#include <unistd.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/character/frames.h"
#include "podium/character/motion.h"
#include "podium/sim/dynamics.h"
#include "sprint_rewards.h"
#include "track.h"

namespace podium::tasks::sprint {

using base::Json;
namespace fs = std::filesystem;

Json PrimitiveSettings::to_json() const {
  return {{"clips", clips},
          {"frames", frames},
          {"hysteresis_rad", hysteresis_rad},
          {"min_stride_s", min_stride_s},
          {"max_stride_s", max_stride_s},
          {"latent", latent},
          {"epochs", epochs},
          {"beta", beta},
          {"reference_strides", reference_strides},
          {"holdout_every", holdout_every},
          {"k", k},
          {"online", online},
          {"online_epochs", online_epochs},
          {"online_buffer", online_buffer}};
}

void StrideCutter::reset() { above_ = false, best_ = 0.0, best_index_ = 0; }

std::optional<std::int64_t> StrideCutter::observe(std::int64_t index, double s) {
  if (!above_) {
    if (s > h_) above_ = true, best_ = s, best_index_ = index;
    return std::nullopt;
  }
  if (s > best_) best_ = s, best_index_ = index;
  if (s >= -h_) return std::nullopt;
  above_ = false;  // the excursion is over: its maximum is a cut
  return best_index_;
}

Json StrideCutter::state() const { return {{"above", above_}, {"best", best_}, {"best_index", best_index_}}; }

void StrideCutter::load_state(const Json& state) {
  above_ = state.at("above").get<bool>();
  best_ = state.at("best").get<double>();
  best_index_ = state.at("best_index").get<std::int64_t>();
}

std::vector<double> resample_stride(std::span<const std::vector<double>> frames, int k) {
  if (frames.size() < 2 || k < 2) throw base::UserError("sprint primitive: a stride needs 2 frames or more and K ≥ 2");
  const std::size_t f = frames.front().size();
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(k) * f);
  const double last = static_cast<double>(frames.size() - 1);
  for (int i = 0; i < k; ++i) {
    const double at = last * i / (k - 1);
    const auto lo = std::min(static_cast<std::size_t>(at), frames.size() - 2);
    const double w = at - static_cast<double>(lo);
    for (std::size_t j = 0; j < f; ++j) out.push_back((1.0 - w) * frames[lo][j] + w * frames[lo + 1][j]);
  }
  return out;
}

std::vector<double> stride_frame(const character::PoseBridge& bridge, const Eigen::VectorXd& q) {
  std::vector<double> frame = bridge.pose(q);
  const Eigen::Quaterniond root = character::quat_at(q, 3);
  const Eigen::Matrix3d heading = character::heading_rotation(character::heading_yaw(root.toRotationMatrix()));
  const Eigen::Vector3d lean = character::log_map(Eigen::Quaterniond(heading.transpose() * root.toRotationMatrix()));
  frame.insert(frame.end(), lean.data(), lean.data() + 3);
  return frame;
}

double thigh_signal(const sim::CharacterModel& model, sim::CharacterData& scratch, const Eigen::VectorXd& q) {
  const SprintBodies bodies = SprintBodies::of(model);
  scratch.q = q;
  sim::forward_kinematics(model, scratch);
  return sagittal_angle(model, scratch, bodies.left_thigh) - sagittal_angle(model, scratch, bodies.right_thigh);
}

StrideRecorder::StrideRecorder(const PrimitiveSettings& settings, double dt_s)
    : settings_(settings), dt_(dt_s), cutter_(settings.hysteresis_rad) {}

void StrideRecorder::reset() {
  cutter_.reset();
  index_ = 0, first_ = 0;
  last_peak_.reset();
  frames_.clear();
}

std::optional<std::vector<double>> StrideRecorder::observe(std::vector<double> frame, double s) {
  frames_.push_back(std::move(frame));
  const std::optional<std::int64_t> peak = cutter_.observe(index_++, s);
  if (!last_peak_) {  // before the first cut only the frames from a possible first cut on are kept
    if (peak) last_peak_ = peak;
    const std::int64_t keep = last_peak_ ? *last_peak_ : cutter_.candidate().value_or(index_);
    frames_.erase(frames_.begin(), frames_.begin() + (keep - first_)), first_ = keep;
    return std::nullopt;
  }
  if (!peak) return std::nullopt;
  const std::int64_t begin = *last_peak_ - first_, end = *peak - first_;  // the stride: [last peak, this peak]
  std::optional<std::vector<double>> stride;
  const double duration = static_cast<double>(*peak - *last_peak_) * dt_;
  if (duration >= settings_.min_stride_s && duration <= settings_.max_stride_s)
    stride = resample_stride(
        std::span(frames_).subspan(static_cast<std::size_t>(begin), static_cast<std::size_t>(end - begin + 1)), settings_.frames);
  frames_.erase(frames_.begin(), frames_.begin() + end), first_ = *peak;
  last_peak_ = peak;
  return stride;
}

Json StrideRecorder::state() const {
  return {{"cutter", cutter_.state()},
          {"index", index_},
          {"first", first_},
          {"last_peak", last_peak_ ? Json(*last_peak_) : Json(nullptr)},
          {"frames", frames_}};
}

void StrideRecorder::load_state(const Json& state) {
  cutter_.load_state(state.at("cutter"));
  index_ = state.at("index").get<std::int64_t>();
  first_ = state.at("first").get<std::int64_t>();
  last_peak_.reset();
  if (!state.at("last_peak").is_null()) last_peak_ = state.at("last_peak").get<std::int64_t>();
  frames_ = state.at("frames").get<std::vector<std::vector<double>>>();
}

learn::PoseDataset strides_from_clips(const sim::ModelPtr& model, double control_hz, const PrimitiveSettings& settings) {
  const character::PoseBridge bridge(model);
  learn::PoseDataset out;
  std::vector<std::string> names = bridge.dof_names();
  std::vector<double> lower = bridge.lower(), upper = bridge.upper();
  for (const char* axis : {"root_lean_x", "root_lean_y", "root_lean_z"})
    names.push_back(axis), lower.push_back(-std::numbers::pi), upper.push_back(std::numbers::pi);
  for (int k = 0; k < settings.frames; ++k)
    for (std::size_t j = 0; j < names.size(); ++j) {
      out.dof_names.push_back("k" + std::to_string(k) + "/" + names[j]);
      out.lower.push_back(lower[j]);
      out.upper.push_back(upper[j]);
    }
  sim::CharacterData scratch(*model);
  for (const std::string& file : settings.clips) {
    if (!fs::is_regular_file(file)) throw base::UserError("sprint primitive: clip " + file + ": no such file");
    const character::Clip read = character::read_deepmimic_clip(model, file);
    for (const character::Clip& clip : {read, character::mirror(read)}) {  // and its mirror image: twice the strides
      StrideRecorder recorder(settings, 1.0 / control_hz);
      const double until = (clip.loop ? 3.0 : 1.0) * clip.duration_s();  // a looping clip (one cycle) three times over
      for (double t = 0.0; t <= until + 1e-9; t += 1.0 / control_hz) {
        const Eigen::VectorXd q = clip.sample(t);
        if (auto stride = recorder.observe(stride_frame(bridge, q), thigh_signal(*model, scratch, q))) {
          for (std::size_t i = 0; i < stride->size(); ++i) (*stride)[i] = std::clamp((*stride)[i], out.lower[i], out.upper[i]);
          out.poses.push_back(std::move(*stride));
        }
      }
    }
  }
  return out;
}

double gaussian_kl(const Eigen::VectorXd& m, const Eigen::VectorXd& s, const Eigen::VectorXd& mu, const Eigen::MatrixXd& sigma) {
  const Eigen::LLT<Eigen::MatrixXd> llt(sigma);
  if (llt.info() != Eigen::Success) throw base::UserError("sprint primitive: the reference covariance is not positive definite");
  const Eigen::MatrixXd inverse = llt.solve(Eigen::MatrixXd::Identity(sigma.rows(), sigma.cols()));
  const Eigen::VectorXd d = mu - m;
  const Eigen::MatrixXd& L = llt.matrixL();
  const double log_det_sigma = 2.0 * L.diagonal().array().log().sum();
  const double log_det_s = 2.0 * s.array().log().sum();
  const double trace = (inverse.diagonal().array() * s.array().square()).sum();
  return 0.5 * (trace + d.dot(inverse * d) - static_cast<double>(m.size()) + log_det_sigma - log_det_s);
}

namespace {

Eigen::VectorXd to_vector(const std::vector<double>& v) { return Eigen::Map<const Eigen::VectorXd>(v.data(), std::ssize(v)); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

SportPrimitive::SportPrimitive(const learn::PoseDataset& strides, const PrimitiveSettings& settings, std::uint64_t seed)
    : settings_(settings) {
  template_ = strides;
  template_.poses.clear();
  learn::PoseDataset train = template_, heldout = template_;
  for (std::size_t i = 0; i < strides.size(); ++i)
    ((i + 1) % static_cast<std::size_t>(settings.holdout_every) == 0 ? heldout : train).poses.push_back(strides.poses[i]);
  if (train.size() < 2)
    throw base::UserError("sprint primitive: " + std::to_string(train.size()) +
                          " training strides in the clips (2 or more needed: longer runs, or more clips)");
  learn::VaeConfig config;
  config.latent_size = settings.latent;
  config.epochs = settings.epochs;
  config.beta = settings.beta;
  phi1_ = std::make_unique<learn::PoseVae>(config, strides.lower, strides.upper, 0, base::derive_seed(seed, 1));
  phi1_->train(train);
  // The reference: n training strides drawn with replacement, their posteriors moment-matched.
  base::Rng rng(base::derive_seed(seed, 2));
  const auto n = static_cast<std::size_t>(settings.reference_strides), d = static_cast<std::size_t>(settings.latent);
  Eigen::MatrixXd means(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(d));
  Eigen::VectorXd variance = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(d));
  for (std::size_t i = 0; i < n; ++i) {
    const auto& stride = train.poses[static_cast<std::size_t>(rng.integer(0, static_cast<std::int64_t>(train.size()) - 1))];
    const learn::PoseVae::Posterior p = phi1_->posterior(stride);
    means.row(static_cast<Eigen::Index>(i)) = to_vector(p.mean).transpose();
    variance += to_vector(p.std).array().square().matrix();
  }
  mu_ = means.colwise().mean().transpose();
  const Eigen::MatrixXd centred = means.rowwise() - mu_.transpose();
  sigma_ =
      centred.transpose() * centred / static_cast<double>(n) + Eigen::MatrixXd(variance.asDiagonal()) / static_cast<double>(n);
  std::vector<double> held, trained;
  for (const auto& s : heldout.poses) held.push_back(kl(s));
  for (const auto& s : train.poses) trained.push_back(kl(s));
  k_ = settings.k > 0.0 ? settings.k : std::log(2.0) / std::max(1e-9, median(held.empty() ? trained : held));
  summary_ = {{"training_strides", train.size()},
              {"heldout_strides", heldout.size()},
              {"k", k_},
              {"median_kl_training", median(trained)},
              {"median_kl_heldout", held.empty() ? Json(nullptr) : Json(median(held))},
              {"reconstruction_rmse_rad", phi1_->reconstruction_rmse(heldout.size() > 0 ? heldout : train)}};
  if (settings.online) {  // Φ2 starts as a copy of Φ1
    // A file of this process and object: trials of one seed may run side by side.
    const fs::path file = fs::temp_directory_path() / ("podium-phi1-" + std::to_string(::getpid()) + "-" +
                                                       std::to_string(reinterpret_cast<std::uintptr_t>(this)) + ".pt");
    phi1_->save(file);
    phi2_ = learn::PoseVae::from_file(file);
    fs::remove(file);
  }
}

SportPrimitive::~SportPrimitive() = default;

std::size_t SportPrimitive::stride_size() const { return phi1_->pose_size(); }

double SportPrimitive::kl(std::span<const double> stride) const {
  std::vector<double> clamped(stride.begin(), stride.end());
  for (std::size_t i = 0; i < clamped.size() && i < template_.lower.size(); ++i)
    clamped[i] = std::clamp(clamped[i], template_.lower[i], template_.upper[i]);
  const learn::PoseVae::Posterior p = (phi2_ ? *phi2_ : *phi1_).posterior(clamped);
  return gaussian_kl(to_vector(p.mean), to_vector(p.std), mu_, sigma_);
}

double SportPrimitive::reward(std::span<const double> stride) const { return std::exp(-k_ * kl(stride)); }

void SportPrimitive::adapt(const std::vector<std::vector<double>>& strides) {
  if (!phi2_ || strides.empty()) return;
  learn::PoseDataset batch = template_;
  for (const auto& s : strides) {
    std::vector<double> clamped = s;
    for (std::size_t i = 0; i < clamped.size(); ++i) clamped[i] = std::clamp(clamped[i], batch.lower[i], batch.upper[i]);
    batch.poses.push_back(std::move(clamped));
  }
  const int epochs = settings_.online_epochs;
  phi2_->train(batch, [epochs](int epoch, double) { return epoch + 1 < epochs; });
}

Json SportPrimitive::summary() const { return summary_; }

void SportPrimitive::save_online(const fs::path& file) const {
  if (phi2_) phi2_->save(file);
}

void SportPrimitive::load_online(const fs::path& file) {
  if (phi2_) phi2_->load(file);
}

}  // namespace podium::tasks::sprint
