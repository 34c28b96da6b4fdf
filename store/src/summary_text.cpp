// The text of `podium summary`: campaign_summary's and compare_campaigns's JSON, for a terminal.
// Tables show 4 significant digits (a reader's precision); --json has the stored doubles.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "podium/store/summary.h"

namespace podium::store {

using base::Json;

namespace {

using Lines = std::vector<std::string>;

// Display width of UTF-8 text (code points; the tables' κ, β, π are one column each).
std::size_t columns_of(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

std::string readable(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

std::string cell_text(const Json& cell) {
  if (cell.is_null()) return "-";
  if (cell.is_string()) return cell.get<std::string>();
  if (cell.is_boolean()) return cell.get<bool>() ? "yes" : "no";
  if (cell.is_number_integer()) return std::to_string(cell.get<long long>());
  if (cell.is_number()) return readable(cell.get<double>());
  return cell.dump();
}

// "name" or "name (unit)".
std::string label(const Json& entry) {
  const std::string unit = entry.value("unit", std::string());
  return entry.value("name", std::string()) + (unit.empty() ? "" : " (" + unit + ")");
}

// "a 0.6, b 0.05" from [{"name", "unit"?, "value"}].
std::string values_text(const Json& named) {
  std::string out;
  for (const auto& v : named) out += (out.empty() ? "" : ", ") + label(v) + " " + cell_text(v["value"]);
  return out;
}

// Rows padded to their widest cell: text left, numbers right.
Lines table_lines(const std::vector<std::string>& header, const std::vector<std::vector<Json>>& rows, const std::string& indent) {
  std::vector<std::size_t> width(header.size(), 0);
  std::vector<bool> left(header.size(), true);
  for (std::size_t i = 0; i < header.size(); ++i) width[i] = columns_of(header[i]);
  for (const auto& row : rows)
    for (std::size_t i = 0; i < row.size() && i < header.size(); ++i) {
      width[i] = std::max(width[i], columns_of(cell_text(row[i])));
      if (row[i].is_number()) left[i] = false;
    }
  Lines out;
  auto line = [&](const std::vector<std::string>& cells) {
    std::string text = indent;
    for (std::size_t i = 0; i < header.size(); ++i) {
      const std::string c = i < cells.size() ? cells[i] : "";
      const std::string pad(width[i] > columns_of(c) ? width[i] - columns_of(c) : 0, ' ');
      text += (left[i] ? c + pad : pad + c) + (i + 1 < header.size() ? "  " : "");
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out.push_back(text);
  };
  line(header);
  for (const auto& row : rows) {
    std::vector<std::string> cells;
    for (const auto& c : row) cells.push_back(cell_text(c));
    line(cells);
  }
  return out;
}

Lines strategy_lines(const Json& stage, bool brief) {
  const Json& strategies = stage["strategies"];
  if (stage["features"].empty()) return {};
  Lines out = {"  strategies: " + std::to_string(strategies.size())};
  if (strategies.empty() || brief) return out;
  std::vector<std::string> header = {"strategy", "trials", "representative"};
  if (!stage["objectives"].empty()) header.push_back(label(stage["objectives"][0]));
  for (const auto& f : stage["features"]) header.push_back(label(f));
  std::vector<std::vector<Json>> rows;
  for (const auto& s : strategies) {
    std::vector<Json> row = {s["label"], s["trials"], s["representative"]["trial"]};
    if (!stage["objectives"].empty()) row.push_back(s["best_objective"]);
    for (const auto& f : s["features"]) row.push_back(f["value"]);
    rows.push_back(row);
  }
  for (auto& l : table_lines(header, rows, "    ")) out.push_back(std::move(l));
  return out;
}

Lines stage_lines(const Json& stage, bool brief) {
  const Json& n = stage["trials"];
  Lines out = {"stage " + std::to_string(stage["index"].get<int>()) + " " + stage["name"].get<std::string>() + " (task " +
               stage["task"].get<std::string>() + ", search " + stage["algorithm"].get<std::string>() +
               "): " + stage["state"].get<std::string>() + ", " + std::to_string(n["done"].get<long long>()) + " of " +
               std::to_string(n["budget"].get<long long>()) + " trials done, " + std::to_string(n["failed"].get<long long>()) +
               " failed"};
  if (!stage["objectives"].empty() && !brief) out.emplace_back("  objectives (the first ranks trials):");
  for (const auto& o : brief ? Json::array() : stage["objectives"])
    out.push_back("    " + label(o) + (o.contains("description") ? ": " + o["description"].get<std::string>() : ""));
  if (stage["best"].is_object()) {
    const Json& b = stage["best"];
    std::string line = "  best: " + b["trial"].get<std::string>() + ": " + values_text(b["objectives"]);
    if (!b["features"].empty()) line += "; " + values_text(b["features"]);
    if (!b["strategy_label"].is_null() && !stage["features"].empty()) line += "; strategy " + b["strategy_label"].dump();
    out.push_back(line);
  }
  for (auto& l : strategy_lines(stage, brief)) out.push_back(std::move(l));
  if (const Json& r = stage["search_result"]; r.is_object() && r.contains("mean")) {
    std::string line = "  search result: mean";
    for (const auto& [name, v] : r["mean"].items()) line += " " + name + " " + cell_text(v);
    if (r.contains("step_sizes")) {
      line += "; step sizes";
      for (const auto& [name, v] : r["step_sizes"].items()) line += " " + name + " " + cell_text(v);
    }
    if (r.contains("generations")) line += "; " + r["generations"].dump() + " generations";
    if (r.value("stopped", false)) line += ", converged (step-size stop)";
    out.push_back(line);
  }
  if (!stage["discovery"].empty() && !stage["features"].empty() && !brief) {
    std::string curve;
    for (const auto& p : stage["discovery"]) curve += (curve.empty() ? "" : " ") + p[1].dump() + "@" + p[0].dump();
    out.push_back("  discovery (strategies@samples): " + curve);
  }
  for (const auto& t : stage["tables"]) {
    out.push_back("  " + t.value("title", std::string("results")));
    std::vector<std::string> header;
    for (const auto& c : t["columns"]) header.push_back(label(c));
    std::vector<std::vector<Json>> rows;
    for (const auto& r : t["rows"]) rows.emplace_back(r.begin(), r.end());
    for (auto& l : table_lines(header, rows, "    ")) out.push_back(std::move(l));
  }
  return out;
}

std::string joined(const Lines& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

}  // namespace

std::string format_summary(const Json& summary, bool brief) {
  const Json& c = summary["campaign"];
  Lines out = {"campaign " + c["id"].dump() + " (" + c["name"].get<std::string>() + "): " + c["state"].get<std::string>()};
  for (const auto& stage : summary["stages"]) {
    out.emplace_back();
    for (auto& l : stage_lines(stage, brief)) out.push_back(std::move(l));
  }
  return joined(out);
}

std::string format_comparison(const Json& comparison) {
  Lines out;
  std::string names;
  for (const auto& s : comparison["campaigns"])
    names += (names.empty() ? "" : " | ") + s["campaign"]["id"].dump() + " " + s["campaign"]["name"].get<std::string>() + " (" +
             s["campaign"]["state"].get<std::string>() + ")";
  out.push_back("campaigns: " + names);
  for (const auto& stage : comparison["stages"]) {
    // Each campaign's block of this stage, side by side.
    std::vector<Lines> blocks;
    for (const auto& s : comparison["campaigns"]) {
      Lines block = {"[" + s["campaign"]["name"].get<std::string>() + "]"};
      for (const auto& st : s["stages"])
        if (st["name"] == stage["name"])
          for (auto& l : stage_lines(st, false)) block.push_back(std::move(l));
      if (block.size() == 1) block.push_back("(no stage " + stage["name"].get<std::string>() + ")");
      blocks.push_back(std::move(block));
    }
    out.emplace_back();
    std::size_t height = 0;
    for (const auto& b : blocks) height = std::max(height, b.size());
    for (std::size_t row = 0; row < height; ++row) {
      std::string line;
      for (std::size_t i = 0; i < blocks.size(); ++i) {
        std::size_t width = 0;
        for (const auto& l : blocks[i]) width = std::max(width, columns_of(l));
        const std::string cell = row < blocks[i].size() ? blocks[i][row] : "";
        line += cell + (i + 1 < blocks.size() ? std::string(width - columns_of(cell), ' ') + "  |  " : "");
      }
      while (!line.empty() && line.back() == ' ') line.pop_back();
      out.push_back(line);
    }
  }
  return joined(out);
}

}  // namespace podium::store
