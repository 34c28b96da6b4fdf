#include "curve_stats.h"

#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "curve_edit.h"
#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/sim/model.h"

namespace podium::tasks::getup_curves {

namespace fs = std::filesystem;
using base::Json;

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr int kStatSamples = 21;  // instants s = 0, 0.05, …, 1 of the mean ± sd curves

ClipLabel read_label(base::ConfigReader& r) {
  ClipLabel l;
  l.clip = r.string("clip", base::required, "the DeepMimic-format motion file, relative to the data root");
  l.model = r.string("model", base::required, "the character it was captured on: a shipped model or a character file");
  l.strategy = r.choice("strategy", base::required, getup_strategies(), "its Bohannon–Lusardi strategy (Fig. 8)");
  l.why = r.string("why", "", "what in its features decided the label");
  return l;
}

// Mean and sample sd (n − 1; null for one value).
Json mean_sd(const std::vector<double>& v) {
  double mean = 0.0;
  for (const double x : v) mean += x / static_cast<double>(v.size());
  if (v.size() < 2) return {{"mean", mean}, {"sd", nullptr}};
  double ss = 0.0;
  for (const double x : v) ss += (x - mean) * (x - mean);
  return {{"mean", mean}, {"sd", std::sqrt(ss / static_cast<double>(v.size() - 1))}};
}

// Per feature in the file's units (m, degrees): the values of `value(row, k)` over the rows, as
// {"h_m": [{"mean", "sd"} × n], ...}.
template <class Value>
Json feature_stats(const std::vector<const ClipRow*>& rows, int n, Value value) {
  static const char* keys[3] = {"h_m", "theta_x_deg", "theta_z_deg"};
  Json out = Json::object();
  for (int f = 0; f < 3; ++f) {
    Json mean = Json::array(), sd = Json::array();
    for (int k = 0; k < n; ++k) {
      std::vector<double> v;
      for (const ClipRow* row : rows) v.push_back(value(*row, f, k) * (f == 0 ? 1.0 : kDegPerRad));
      const Json m = mean_sd(v);
      mean.push_back(m["mean"]);
      sd.push_back(m["sd"]);
    }
    out[keys[f]] = {{"mean", mean}, {"sd", sd}};
  }
  return out;
}

Json strategy_json(const std::string& strategy, const std::vector<const ClipRow*>& rows, const std::string& method) {
  std::vector<double> durations, rises;
  Json clips = Json::array();
  ControlPoints mean = ControlPoints::Zero();
  for (const ClipRow* row : rows) {
    clips.push_back(row->label.clip);
    durations.push_back(row->extraction.curve.duration_s);
    rises.push_back(row->rise_s);
    mean += row->extraction.curve.points / static_cast<double>(rows.size());
  }
  StyleCurve curve;
  curve.name = strategy;
  curve.duration_s = mean_sd(durations)["mean"].get<double>();
  curve.points = mean;
  curve.start = {CurveStart::Kind::drop, "", 0, mean(2, 0) < 0.5 * std::numbers::pi};
  curve.source = "the mean of " + std::to_string(rows.size()) + " clips' " + method + " curves (podium tool getup_curves stats)";
  const Json points_sd =
      feature_stats(rows, kControlPoints, [](const ClipRow& r, int f, int k) { return r.extraction.curve.points(f, k); });
  Json sd = Json::object();
  for (const auto& [key, value] : points_sd.items()) sd[key] = value["sd"];
  Json s = Json::array();
  for (int i = 0; i < kStatSamples; ++i) s.push_back(static_cast<double>(i) / (kStatSamples - 1));
  Json samples = feature_stats(rows, kStatSamples, [](const ClipRow& r, int f, int i) {
    return r.extraction.curve.at(static_cast<double>(i) / (kStatSamples - 1))(f);
  });
  samples["s"] = s;
  return {{"strategy", strategy},
          {"clips", clips},
          {"duration_s", mean_sd(durations)},
          {"rise_s", mean_sd(rises)},
          {"mean_curve", style_curve_json(curve)},
          {"control_points_sd", sd},
          {"samples", samples}};
}

std::string fixed(const Json& v, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << v.get<double>();
  return out.str();
}

std::string plus_minus(const Json& m, int digits) {
  return fixed(m["mean"], digits) + (m["sd"].is_null() ? "" : " ± " + fixed(m["sd"], digits));
}

}  // namespace

const std::vector<std::string>& getup_strategies() {
  static const std::vector<std::string> names{"sit_up_roll_over", "side_sit_half_kneel_pivot", "quadruped_push_up_supine",
                                              "quadruped_push_up_prone"};
  return names;
}

sim::ModelPtr load_character(const std::string& name_or_file, const fs::path& root) {
  const fs::path p(name_or_file);
  const std::string ext = p.extension().string();
  if (ext != ".txt" && ext != ".json") return sim::load_shipped_model(name_or_file);
  const fs::path file = p.is_relative() && !root.empty() ? root / p : p;
  if (!fs::is_regular_file(file)) throw base::UserError(file.string() + ": no such character file");
  return ext == ".txt" ? sim::load_deepmimic(file) : sim::load_model(file);
}

std::vector<ClipLabel> load_clip_labels(const fs::path& path) {
  const Json json = base::read_json_file(path);
  return base::ConfigReader::parse(json, path.string(), [](base::ConfigReader& r) {
    r.string("description", "", "what the labels are and how they were decided");
    auto labels = r.objects("clips", read_label, "one entry per clip");
    if (labels.empty()) r.fail("clips", "is empty: a label file names at least one clip");
    return labels;
  });
}

CurveStats curve_stats(const std::vector<ClipLabel>& labels, const StatsOptions& options) {
  CurveStats stats;
  const sim::ModelPtr to = options.to_model.empty() ? nullptr : load_character(options.to_model, options.data_root);
  const double to_height = to ? standing_neck_height(*to) : 1.0;
  for (const ClipLabel& label : labels) {
    const sim::ModelPtr model = load_character(label.model, options.data_root);
    const fs::path file = fs::path(label.clip).is_relative() ? options.data_root / label.clip : fs::path(label.clip);
    if (!fs::is_regular_file(file))
      throw base::UserError(file.string() + ": no such clip (from the label of " + label.clip + ")");
    const double scale = to ? to_height / standing_neck_height(*model) : 1.0;
    Extraction e = extract_curve(character::read_deepmimic_clip(model, file),
                                 {options.method, fs::path(label.clip).stem().string(), label.clip, scale});
    const double rise = rise_time_s(e.curve);
    stats.rows.push_back({label, std::move(e), scale, rise});
  }
  const std::string method = options.method == ExtractMethod::samples ? "9-sample" : "least-squares";
  Json clips = Json::array(), strategies = Json::array();
  for (const ClipRow& row : stats.rows) {
    const Eigen::Vector3d rms = row.extraction.rms;
    clips.push_back({{"clip", row.label.clip},
                     {"strategy", row.label.strategy},
                     {"frames", row.extraction.track.times_s.size()},
                     {"duration_s", row.extraction.curve.duration_s},
                     {"height_scale", row.height_scale},
                     {"start_theta_z_deg", row.extraction.track.features.front()(2) * kDegPerRad},
                     {"rise_s", row.rise_s},
                     {"rms", {{"h_m", rms(0)}, {"theta_x_deg", rms(1) * kDegPerRad}, {"theta_z_deg", rms(2) * kDegPerRad}}}});
  }
  for (const std::string& strategy : getup_strategies()) {
    std::vector<const ClipRow*> rows;
    for (const ClipRow& row : stats.rows)
      if (row.label.strategy == strategy) rows.push_back(&row);
    if (!rows.empty()) strategies.push_back(strategy_json(strategy, rows, method));
  }
  stats.json = {{"method", method}, {"to_model", options.to_model}, {"clips", clips}, {"strategies", strategies}};
  return stats;
}

std::string format_curve_stats(const CurveStats& stats) {
  std::ostringstream out;
  out << std::left << std::setw(36) << "clip" << std::setw(27) << "strategy" << std::right << std::setw(7) << "frames"
      << std::setw(7) << "T_s" << std::setw(10) << "z0_deg" << std::setw(8) << "rise_s" << std::setw(10) << "rms_h_m"
      << std::setw(10) << "rms_x_deg" << std::setw(10) << "rms_z_deg"
      << "\n";
  for (const Json& c : stats.json["clips"]) {
    const Json& rms = c["rms"];
    out << std::left << std::setw(36) << fs::path(c["clip"].get<std::string>()).filename().string() << std::setw(27)
        << c["strategy"].get<std::string>() << std::right << std::setw(7) << c["frames"].get<int>() << std::setw(7)
        << fixed(c["duration_s"], 2) << std::setw(10) << fixed(c["start_theta_z_deg"], 1) << std::setw(8) << fixed(c["rise_s"], 2)
        << std::setw(10) << fixed(rms["h_m"], 3) << std::setw(10) << fixed(rms["theta_x_deg"], 1) << std::setw(10)
        << fixed(rms["theta_z_deg"], 1) << "\n";
  }
  out << "\n"
      << std::left << std::setw(27) << "strategy" << std::setw(7) << "clips" << std::setw(16) << "T_s"
      << "rise_s\n";
  for (const Json& s : stats.json["strategies"])
    out << std::left << std::setw(27) << s["strategy"].get<std::string>() << std::setw(7) << s["clips"].size() << std::setw(16)
        << plus_minus(s["duration_s"], 2) << plus_minus(s["rise_s"], 2) << "\n";
  return out.str();
}

}  // namespace podium::tasks::getup_curves
