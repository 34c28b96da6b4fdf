#pragma once
/// Style curves from motion clips (curve get-up seed §4.1: "evaluating the features for each
/// animation and then sampling them at nine equally distributed instances in time"), and a
/// least-squares alternative that fits the 9 control points to every frame. Each reports how far
/// its curve lies from the clip's features, as an RMS per feature over the clip's frames.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "podium/character/motion.h"
#include "style_curve.h"

namespace podium::tasks::getup_curves {

/// A clip's features frame by frame (style_features.h, on the clip's own model, flat ground).
struct FeatureTrack {
  std::vector<double> times_s;
  std::vector<StyleFeatures> features;
};
/// `height_scale` multiplies h (to carry a clip's heights to a character of other proportions,
/// e.g. the ratio of the two characters' standing neck heights; 1 keeps them).
FeatureTrack feature_track(const character::Clip& clip, double height_scale = 1.0);

/// The neck base's height above the soles in the model's standing pose (joints at rest, the lowest
/// geom point put on the ground): the h of that character standing. The ratio of two characters'
/// values is the height_scale that carries one's clips to the other (DeepMimic's humanoid3d to
/// humanoid34: about 1.17).
double standing_neck_height(const sim::CharacterModel& model);

/// Per feature, the RMS over the track's frames of p(t/T) − feature (h in m, angles in rad), the
/// curve started at the track's first time.
Eigen::Vector3d curve_rms(const StyleCurve& curve, const FeatureTrack& track);

enum class ExtractMethod {
  samples,       ///< §4.1: control points = the features at s = 0, 1/8, …, 1 (clip poses interpolated)
  least_squares  ///< control points minimising the squared error to every frame, within the file's ranges
};

struct ExtractOptions {
  ExtractMethod method = ExtractMethod::least_squares;
  std::string name;       ///< the curve's name
  std::string clip_file;  ///< the clip's file: the curve starts at its frame 0 and names it as its source
  double height_scale = 1.0;
};

struct Extraction {
  StyleCurve curve;     ///< T = the clip's duration
  Eigen::Vector3d rms;  ///< curve_rms of the curve against the clip's frames
  FeatureTrack track;   ///< the clip's features, frame by frame
};

/// Throws base::UserError naming the clip file when the clip has fewer than 9 frames or no duration.
Extraction extract_curve(const character::Clip& clip, const ExtractOptions& options);

}  // namespace podium::tasks::getup_curves
