#pragma once
/// A labelled table of get-up clips by strategy and each strategy's mean ± sd curves (curve get-up
/// seed §6.2, Fig. 8: the reference clips classified by hand into Bohannon and Lusardi's
/// strategies, the mean and standard deviation of their feature curves per class, a guide for
/// authoring). The labels are data: a label file names each clip, the skeleton it was captured
/// on and its strategy.
#include <filesystem>
#include <string>
#include <vector>

#include "curve_extraction.h"
#include "podium/base/json.h"

namespace podium::tasks::getup_curves {

/// The four strategies of Fig. 8, as label files spell them: "sit_up_roll_over",
/// "side_sit_half_kneel_pivot", "quadruped_push_up_supine", "quadruped_push_up_prone".
const std::vector<std::string>& getup_strategies();

/// A character to read a clip on: a shipped model's name ("humanoid34"), a DeepMimic character
/// file (*.txt) or a model file of the project's format (*.json); a relative file is looked up under
/// `root` (when not empty). Throws base::UserError naming what it could not read.
sim::ModelPtr load_character(const std::string& name_or_file, const std::filesystem::path& root = {});

/// One entry of a label file.
struct ClipLabel {
  std::string clip;      ///< the DeepMimic-format motion file, relative to the data root
  std::string model;     ///< the character it was captured on (load_character)
  std::string strategy;  ///< one of getup_strategies()
  std::string why;       ///< what in the clip's features decided the label
};

/// A label file: {"description"?, "clips": [{"clip", "model", "strategy", "why"?}, ...]}; errors
/// name the file, the JSON path and the value.
std::vector<ClipLabel> load_clip_labels(const std::filesystem::path& path);

struct StatsOptions {
  std::filesystem::path data_root;  ///< the labels' clip and model paths are relative to it
  ExtractMethod method = ExtractMethod::least_squares;
  std::string to_model = "humanoid34";  ///< heights carried to this character's proportions ("" keeps each clip's)
};

/// One clip's row of the table.
struct ClipRow {
  ClipLabel label;
  Extraction extraction;  ///< its curve (heights carried), RMS and feature track
  double height_scale = 1.0;
  double rise_s = 0.0;  ///< rise_time_s of its curve
};

/// The table and per strategy (in getup_strategies' order, those with clips) the statistics:
/// {"method", "to_model", "clips": [{"clip", "strategy", "frames", "duration_s", "start_theta_z_deg",
///   "rise_s", "rms": {"h_m", "theta_x_deg", "theta_z_deg"}}],
///  "strategies": [{"strategy", "clips": [...], "duration_s": {"mean", "sd"}, "rise_s": {"mean", "sd"},
///   "mean_curve": a curve file's object (the mean control points over the mean T, a drop start on the
///   side the clips start on), "control_points_sd": {"h_m", "theta_x_deg", "theta_z_deg"} (9 each),
///   "samples": {"s": [21], "h_m": {"mean", "sd"}, "theta_x_deg": {...}, "theta_z_deg": {...}}}]}.
/// Curves are compared in normalised time s = t/T; an sd is the sample standard deviation (n − 1),
/// null for a class of one clip.
struct CurveStats {
  std::vector<ClipRow> rows;
  base::Json json;
};
CurveStats curve_stats(const std::vector<ClipLabel>& labels, const StatsOptions& options);

/// The table for people: one row per clip, then one per strategy (T and rise time mean ± sd).
std::string format_curve_stats(const CurveStats& stats);

}  // namespace podium::tasks::getup_curves
