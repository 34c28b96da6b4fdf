#include "curve_tool.h"

#include <boost/program_options.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "curve_edit.h"
#include "curve_extraction.h"
#include "curve_stats.h"
#include "podium/base/error.h"

namespace podium::tasks::getup_curves {

namespace fs = std::filesystem;
namespace po = boost::program_options;
using base::Json;

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct Parsed {
  po::variables_map vm;
  bool help = false;
};

// Parses a command's arguments; `help` when --help was given (the options are printed on `out`).
Parsed parse(const std::vector<std::string>& args, po::options_description options,
             const po::positional_options_description& positional, const std::string& synopsis, std::ostream& out) {
  options.add_options()("help,h", "show this help");
  Parsed p;
  po::store(po::command_line_parser(std::vector<std::string>(args.begin() + 1, args.end()))
                .options(options)
                .positional(positional)
                .run(),
            p.vm);
  if (p.vm.count("help")) {
    out << "usage: podium tool getup_curves " << args[0] << " " << synopsis << "\n\n" << options << "\n";
    p.help = true;
    return p;
  }
  po::notify(p.vm);
  return p;
}

// v to 1/per_unit: a power of ten divided last, so the double is the one nearest the decimal.
double rounded(double v, double per_unit) { return std::round(v * per_unit) / per_unit; }

// `text` with every line after the first indented two more spaces (a nested object).
std::string indented(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '\n' ? std::string("\n  ") : std::string(1, c);
  return out;
}

// A curve file as the shipped ones are written (name, T, start, source, then one line of 9 numbers
// per feature), with T and heights to 0.1 ms and 0.1 mm and angles to 0.01°: far below anything a
// get-up can follow, and a file people can read and diff.
std::string curve_file_text(const StyleCurve& curve) {
  const Json j = style_curve_json(curve);
  std::ostringstream text;
  text << "{\n  \"name\": " << j["name"].dump() << ",\n  \"duration_s\": " << Json(rounded(curve.duration_s, 1e4)).dump()
       << ",\n  \"start\": " << indented(j["start"].dump(2)) << ",\n  \"source\": " << j["source"].dump()
       << ",\n  \"control_points\": {";
  const char* keys[3] = {"h_m", "theta_x_deg", "theta_z_deg"};
  for (int f = 0; f < 3; ++f) {
    text << (f ? "," : "") << "\n    \"" << keys[f] << "\": [";
    const Json& values = j["control_points"][keys[f]];
    for (std::size_t k = 0; k < values.size(); ++k)
      text << (k ? ", " : "") << Json(rounded(values[k].get<double>(), f == 0 ? 1e4 : 1e2)).dump();
    text << "]";
  }
  text << "\n  }\n}\n";
  return text.str();
}

// Written whole: a temporary file in the same folder, then renamed into place.
void save(const fs::path& out, const StyleCurve& curve) {
  const fs::path tmp = out.string() + ".tmp";
  {
    std::ofstream file(tmp);
    if (!(file << curve_file_text(curve)) || !file.flush())
      throw base::RuntimeError(out.string() + ": cannot write the curve file");
  }
  fs::rename(tmp, out);
}

std::string fixed(double v, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << v;
  return out.str();
}

std::string rms_text(const Eigen::Vector3d& rms) {
  return "RMS h " + fixed(rms(0), 3) + " m, θ_x " + fixed(rms(1) * kDegPerRad, 1) + "°, θ_z " + fixed(rms(2) * kDegPerRad, 1) +
         "°";
}

// A relative path under `root` (when given), else as written.
fs::path under(const fs::path& root, const std::string& path) {
  return fs::path(path).is_relative() && !root.empty() ? root / path : fs::path(path);
}

// `file` as a curve file in `folder` names it: relative to the folder (curve_env.h reads a clip
// start's relative path against its curve file's folder).
std::string relative_to_folder_of(const fs::path& file, const fs::path& curve_file) {
  const fs::path rel = fs::absolute(file).lexically_normal().lexically_relative(fs::absolute(curve_file).parent_path());
  return rel.empty() ? fs::absolute(file).string() : rel.string();
}

void write_track(const fs::path& path, const FeatureTrack& track) {
  std::ofstream csv(path);
  if (!csv) throw base::RuntimeError(path.string() + ": cannot write the feature track");
  csv << "t_s,h_m,theta_x_deg,theta_z_deg\n";
  for (std::size_t i = 0; i < track.times_s.size(); ++i)
    csv << track.times_s[i] << "," << track.features[i](0) << "," << track.features[i](1) * kDegPerRad << ","
        << track.features[i](2) * kDegPerRad << "\n";
}

int extract(const std::vector<std::string>& args, std::ostream& out) {
  po::options_description o("extract options");
  o.add_options()("clip", po::value<std::string>()->required(), "the DeepMimic-format motion file")(
      "out", po::value<std::string>()->required(), "the curve file to write")(
      "method", po::value<std::string>()->default_value("fit"), "fit (least squares over every frame) or samples (§4.1's 9)")(
      "model", po::value<std::string>()->default_value("humanoid34"),
      "the character the clip was captured on: a shipped model or a character file (*.txt DeepMimic, *.json)")(
      "to", po::value<std::string>()->default_value("humanoid34"),
      "carry the heights to this character's proportions (standing neck heights' ratio); none: keep them")(
      "name", po::value<std::string>(), "the curve's name (default: the clip's file name)")(
      "start", po::value<std::string>()->default_value("clip"), "clip (its first frame), supine or prone (a ragdoll drop)")(
      "data", po::value<std::string>(), "a folder the clip's and the model's relative paths are under")(
      "track", po::value<std::string>(), "also write the clip's features frame by frame (CSV: t_s, h_m, θ_x°, θ_z°)");
  po::positional_options_description pos;
  pos.add("clip", 1);
  const Parsed p = parse(args, o, pos,
                         "CLIP --out FILE [--method fit|samples] [--model MODEL] [--to MODEL|none] [--name NAME] "
                         "[--start clip|supine|prone] [--data DIR] [--track FILE.csv]",
                         out);
  if (p.help) return 0;
  const auto& vm = p.vm;
  const std::string method = vm["method"].as<std::string>(), start = vm["start"].as<std::string>();
  if (method != "fit" && method != "samples") throw base::UserError("--method \"" + method + "\": not fit or samples");
  if (start != "clip" && start != "supine" && start != "prone")
    throw base::UserError("--start \"" + start + "\": not clip, supine or prone");
  const fs::path root = vm.count("data") ? fs::path(vm["data"].as<std::string>()) : fs::path();
  const std::string clip_arg = vm["clip"].as<std::string>(), model_arg = vm["model"].as<std::string>();
  const fs::path clip_file = under(root, clip_arg), out_file = vm["out"].as<std::string>();
  if (!fs::is_regular_file(clip_file)) throw base::UserError(clip_file.string() + ": no such clip");
  const sim::ModelPtr model = load_character(model_arg, root);
  const std::string to = vm["to"].as<std::string>();
  const double scale = to == "none" ? 1.0 : standing_neck_height(*load_character(to, root)) / standing_neck_height(*model);

  ExtractOptions options;
  options.method = method == "samples" ? ExtractMethod::samples : ExtractMethod::least_squares;
  options.name = vm.count("name") ? vm["name"].as<std::string>() : clip_file.stem().string();
  options.clip_file = relative_to_folder_of(clip_file, out_file);
  options.height_scale = scale;
  Extraction e = extract_curve(character::read_deepmimic_clip(model, clip_file), options);
  if (start != "clip") e.curve.start = {CurveStart::Kind::drop, "", 0, start == "supine"};
  e.curve.source = (method == "samples" ? "the 9 samples of §4.1 of " : "the least-squares fit to ") + clip_arg + " on " +
                   model_arg + (to == "none" ? "" : ", heights × " + fixed(scale, 3) + " to " + to) + "; " + rms_text(e.rms) +
                   (start == "clip" ? "" : "; starts as a " + start + " drop") + " (podium tool getup_curves extract)";
  save(out_file, e.curve);
  if (vm.count("track")) write_track(vm["track"].as<std::string>(), e.track);
  const double x0 = e.track.features.front()(1) * kDegPerRad, z0 = e.track.features.front()(2) * kDegPerRad;
  // The label file's reading of a start (data/getup_labels.json): θ_z within 45° of lying, else a side.
  const std::string lying = z0 < 45.0    ? "on the back"
                            : z0 > 135.0 ? "on the front"
                                         : (x0 > 90.0 ? "on the right side" : "on the left side");
  out << e.curve.name << ": " << (method == "samples" ? "9 samples" : "least-squares fit") << " of " << clip_file.string() << " ("
      << e.track.times_s.size() << " frames, T " << fixed(e.curve.duration_s, 2) << " s, heights × " << fixed(scale, 3) << "); "
      << rms_text(e.rms) << "; starts at θ_x " << fixed(x0, 1) << "°, θ_z " << fixed(z0, 1) << "° (" << lying << "); rise at "
      << fixed(rise_time_s(e.curve), 2) << " s -> " << out_file.string() << "\n";
  return 0;
}

// "FEATURE:INDEX:DELTA" of --move.
StyleCurve apply_move(const StyleCurve& curve, const std::string& spec) {
  const auto a = spec.find(':'), b = spec.rfind(':');
  const std::string bad = "--move \"" + spec + "\": not FEATURE:INDEX:DELTA (e.g. h:4:0.05, theta_z:2:-10; angles in degrees)";
  if (a == std::string::npos || a == b) throw base::UserError(bad);
  try {
    std::size_t used_index = 0, used_delta = 0;
    const std::string index_text = spec.substr(a + 1, b - a - 1), delta_text = spec.substr(b + 1);
    const int index = std::stoi(index_text, &used_index);
    const double delta = std::stod(delta_text, &used_delta);
    if (used_index != index_text.size() || used_delta != delta_text.size()) throw base::UserError(bad);
    return move_control_point(curve, spec.substr(0, a), index, delta);
  } catch (const std::logic_error&) {  // stoi / stod: no number, or out of range
    throw base::UserError(bad);
  }
}

int edit(const std::vector<std::string>& args, std::ostream& out) {
  po::options_description o("edit options");
  o.add_options()("curve", po::value<std::string>()->required(), "the curve file to edit")(
      "out", po::value<std::string>()->required(), "the new curve file")(
      "shift-rise", po::value<double>()->default_value(0.0),
      "S: the rise S seconds later (earlier when negative), the start, the end and T kept")(
      "scale-T", po::value<double>()->default_value(1.0), "F: T × F, the control points kept")(
      "move", po::value<std::vector<std::string>>()->composing(),
      "FEATURE:INDEX:DELTA: control point INDEX (0-8) of h, theta_x or theta_z moved by DELTA (m or degrees); repeatable")(
      "name", po::value<std::string>(), "the new curve's name (default: the file name of --out)");
  po::positional_options_description pos;
  pos.add("curve", 1);
  const Parsed p =
      parse(args, o, pos, "CURVE --out FILE [--shift-rise S] [--scale-T F] [--move FEATURE:INDEX:DELTA]... [--name NAME]", out);
  if (p.help) return 0;
  const auto& vm = p.vm;
  const fs::path in_file = vm["curve"].as<std::string>(), out_file = vm["out"].as<std::string>();
  const StyleCurve original = load_style_curve(in_file);
  const double rise_before = rise_time_s(original);
  // The order is fixed: the rise is shifted on the original T, then T scaled, then points moved.
  StyleCurve c = shift_rise(original, vm["shift-rise"].as<double>());
  c = scale_duration(c, vm["scale-T"].as<double>());
  if (vm.count("move"))
    for (const std::string& m : vm["move"].as<std::vector<std::string>>()) c = apply_move(c, m);
  c.name = vm.count("name") ? vm["name"].as<std::string>() : out_file.stem().string();
  c.source = "edited from " + original.name + " (" + original.source + ")" + c.source.substr(original.source.size()) +
             " (podium tool getup_curves edit)";
  if (c.start.kind == CurveStart::Kind::clip && fs::path(c.start.clip).is_relative())  // still the same clip from --out's folder
    c.start.clip = relative_to_folder_of(in_file.parent_path() / c.start.clip, out_file);
  save(out_file, c);
  out << c.name << ": rise " << fixed(rise_before, 2) << " -> " << fixed(rise_time_s(c), 2) << " s, T "
      << fixed(original.duration_s, 2) << " -> " << fixed(c.duration_s, 2) << " s -> " << out_file.string() << "\n";
  return 0;
}

int stats(const std::vector<std::string>& args, std::ostream& out) {
  po::options_description o("stats options");
  o.add_options()("labels", po::value<std::string>()->required(), "the label file (JSON: clips, their models and strategies)")(
      "data", po::value<std::string>(), "the data root the labels' paths are under (default: $PODIUM_SHARED_DIR/data)")(
      "out", po::value<std::string>(), "write the table and each strategy's mean ± sd curves here (JSON)")(
      "method", po::value<std::string>()->default_value("fit"), "fit or samples: how each clip's curve is extracted")(
      "to", po::value<std::string>()->default_value("humanoid34"), "carry every clip's heights to this character; none: keep");
  po::positional_options_description pos;
  pos.add("labels", 1);
  const Parsed p = parse(args, o, pos, "LABELS [--data DIR] [--out FILE] [--method fit|samples] [--to MODEL|none]", out);
  if (p.help) return 0;
  const auto& vm = p.vm;
  const std::string method = vm["method"].as<std::string>();
  if (method != "fit" && method != "samples") throw base::UserError("--method \"" + method + "\": not fit or samples");
  StatsOptions options;
  if (vm.count("data")) options.data_root = vm["data"].as<std::string>();
  else if (const char* shared = std::getenv("PODIUM_SHARED_DIR")) options.data_root = fs::path(shared) / "data";
  else throw base::UserError("no data root: give --data DIR or set PODIUM_SHARED_DIR (the labels' paths are under its data/)");
  options.method = method == "samples" ? ExtractMethod::samples : ExtractMethod::least_squares;
  options.to_model = vm["to"].as<std::string>() == "none" ? "" : vm["to"].as<std::string>();
  const CurveStats s = curve_stats(load_clip_labels(vm["labels"].as<std::string>()), options);
  out << format_curve_stats(s);
  if (vm.count("out")) {
    base::write_json_file_atomic(vm["out"].as<std::string>(), s.json);
    out << "-> " << vm["out"].as<std::string>() << "\n";
  }
  return 0;
}

}  // namespace

std::vector<plugins::ToolCommand> curve_tool_commands() {
  return {{"extract",
           "CLIP --out FILE [--method fit|samples] [--model MODEL] [--to MODEL|none] [--name NAME] [--start clip|supine|prone]",
           "a style curve from a clip's features: §4.1's 9 samples or a least-squares fit, with its RMS error"},
          {"edit", "CURVE --out FILE [--shift-rise S] [--scale-T F] [--move FEATURE:INDEX:DELTA]...",
           "a new curve file: the rise S s later or earlier, T scaled, control points moved"},
          {"stats", "LABELS [--data DIR] [--out FILE] [--method fit|samples]",
           "a table of labelled clips by Bohannon–Lusardi strategy and each strategy's mean ± sd curves (Fig. 8)"}};
}

int run_curve_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  const std::string command = args.empty() ? "" : args[0];
  try {
    if (command == "extract") return extract(args, out);
    if (command == "edit") return edit(args, out);
    if (command == "stats") return stats(args, out);
    err << "podium tool getup_curves: no command \"" << command << "\" (extract, edit, stats)\n";
    return 2;
  } catch (const po::error& e) {
    err << "podium tool getup_curves " << command << ": " << e.what() << " (see --help)\n";
    return 2;
  } catch (const base::UserError& e) {
    err << "podium tool getup_curves " << command << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << "podium tool getup_curves " << command << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace podium::tasks::getup_curves
