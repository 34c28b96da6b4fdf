#include "curve_extraction.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "podium/base/error.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::getup_curves {

namespace {

StyleFeatures features_of(const StyleFeatureReader& read, const Eigen::VectorXd& q, sim::CharacterData& scratch,
                          double height_scale) {
  StyleFeatures w = read.at(q, scratch);
  w(0) *= height_scale;
  return w;
}

// §4.1's extraction: the features at nine equally spaced instants become the control points.
ControlPoints sampled_points(const character::Clip& clip, double height_scale) {
  const StyleFeatureReader read(*clip.model);
  sim::CharacterData scratch(*clip.model);
  ControlPoints points;
  for (int k = 0; k < kControlPoints; ++k) {
    const double t = clip.duration_s() * k / (kControlPoints - 1);
    points.col(k) = features_of(read, clip.sample(t), scratch, height_scale);
  }
  return points;
}

// min ‖A x − f‖² with lo ≤ x ≤ hi by active sets (Lawson & Hanson's scheme for a box): solve on
// the free entries with the others held at a bound; hold the free entries that leave the box;
// free a held entry whose gradient points into the box; stop when neither happens.
Eigen::VectorXd box_least_squares(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, double lo, double hi) {
  const Eigen::Index n = a.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> held(static_cast<std::size_t>(n), false);
  for (int iteration = 0; iteration < 4 * n + 4; ++iteration) {
    std::vector<Eigen::Index> free;
    Eigen::VectorXd rhs = f;
    for (Eigen::Index k = 0; k < n; ++k) {
      if (held[static_cast<std::size_t>(k)]) rhs -= a.col(k) * x(k);
      else free.push_back(k);
    }
    if (!free.empty()) {
      Eigen::MatrixXd af(a.rows(), static_cast<Eigen::Index>(free.size()));
      for (std::size_t j = 0; j < free.size(); ++j) af.col(static_cast<Eigen::Index>(j)) = a.col(free[j]);
      const Eigen::VectorXd xf = af.colPivHouseholderQr().solve(rhs);
      for (std::size_t j = 0; j < free.size(); ++j) x(free[j]) = xf(static_cast<Eigen::Index>(j));
    }
    bool left_the_box = false;
    for (const Eigen::Index k : free) {
      if (x(k) >= lo && x(k) <= hi) continue;
      x(k) = std::clamp(x(k), lo, hi);
      held[static_cast<std::size_t>(k)] = left_the_box = true;
    }
    if (left_the_box) continue;
    const Eigen::VectorXd gradient = a.transpose() * (a * x - f);
    Eigen::Index release = -1;
    double steepest = 1e-12 * (1.0 + gradient.cwiseAbs().maxCoeff());
    for (Eigen::Index k = 0; k < n; ++k) {
      const bool inward = (x(k) <= lo && gradient(k) < 0.0) || (x(k) >= hi && gradient(k) > 0.0);
      if (held[static_cast<std::size_t>(k)] && inward && std::abs(gradient(k)) > steepest) {
        steepest = std::abs(gradient(k));
        release = k;
      }
    }
    if (release < 0) break;
    held[static_cast<std::size_t>(release)] = false;
  }
  return x;
}

// Least squares over every frame, each feature's control points within what a curve file accepts
// (style_curve.h: h in [0, 3] m, angles in [0, π]): row k of A is the basis at s_i = t_i / T.
ControlPoints fitted_points(const FeatureTrack& track, double duration_s) {
  const auto n = static_cast<Eigen::Index>(track.times_s.size());
  Eigen::MatrixXd a(n, kControlPoints);
  Eigen::MatrixXd f(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto frame = static_cast<std::size_t>(i);
    a.row(i) = bspline_basis((track.times_s[frame] - track.times_s.front()) / duration_s).transpose();
    f.row(i) = track.features[frame].transpose();
  }
  ControlPoints points;
  points.row(0) = box_least_squares(a, f.col(0), 0.0, 3.0).transpose();
  for (int feature = 1; feature < 3; ++feature)
    points.row(feature) = box_least_squares(a, f.col(feature), 0.0, std::numbers::pi).transpose();
  return points;
}

}  // namespace

FeatureTrack feature_track(const character::Clip& clip, double height_scale) {
  const StyleFeatureReader read(*clip.model);
  sim::CharacterData scratch(*clip.model);
  FeatureTrack track;
  track.times_s = clip.times_s;
  for (const Eigen::VectorXd& q : clip.poses) track.features.push_back(features_of(read, q, scratch, height_scale));
  return track;
}

double standing_neck_height(const sim::CharacterModel& model) {
  sim::CharacterData scratch(model);
  const double neck_z = StyleFeatureReader(model).at(model.standing_pose(), scratch)(0);
  return neck_z - sim::lowest_geom_point(model, scratch);
}

Eigen::Vector3d curve_rms(const StyleCurve& curve, const FeatureTrack& track) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < track.times_s.size(); ++i) {
    const Eigen::Vector3d e = curve.target(track.times_s[i], track.times_s.front()) - track.features[i];
    sum += e.cwiseAbs2();
  }
  return (sum / static_cast<double>(std::max<std::size_t>(track.times_s.size(), 1))).cwiseSqrt();
}

Extraction extract_curve(const character::Clip& clip, const ExtractOptions& options) {
  if (clip.size() < static_cast<std::size_t>(kControlPoints) || !(clip.duration_s() > 0.0))
    throw base::UserError(options.clip_file + ": " + std::to_string(clip.size()) + " frames over " +
                          std::to_string(clip.duration_s()) + " s; a curve needs at least " + std::to_string(kControlPoints) +
                          " frames and a duration");
  Extraction out;
  out.track = feature_track(clip, options.height_scale);
  StyleCurve& curve = out.curve;
  curve.name = options.name;
  curve.duration_s = clip.duration_s();
  curve.points = options.method == ExtractMethod::samples ? sampled_points(clip, options.height_scale)
                                                          : fitted_points(out.track, curve.duration_s);
  curve.start = {CurveStart::Kind::clip, options.clip_file, 0, true};
  curve.source =
      std::string(options.method == ExtractMethod::samples ? "9 samples of " : "least-squares fit to ") + options.clip_file;
  out.rms = curve_rms(curve, out.track);
  return out;
}

}  // namespace podium::tasks::getup_curves
