#pragma once
// A recorded pool of trials as a table: each recorded take-off's parameters and what its trial
// gave (success, strategy feature, bar reached, nearest captured technique), exported from a
// campaign stage by export_pool.py. Searches replay over it by lookup: parameters x read as the
// recorded row nearest to x in the box scaled to [0,1]^d, so a search over a pool is restricted
// to the pool's points. README.md describes the file.
//
// Plain data (base only): the box and features stay the JSON a task describes them with, beside
// the ranges a lookup needs, so the `pool` plugin depends on plugins and base alone. The search
// side (search::Space, Feature, Outcome) is bench/search/pool_replay.h's adapter.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::tasks::pool {

/// One recorded trial.
struct PoolRow {
  std::int64_t trial = 0;        ///< its index in the recorded stage
  std::vector<double> params;    ///< in the table's parameter order
  bool finished = true;          ///< false: the trial itself failed (no result)
  bool success = false;          ///< the task's success rule (a jump: it cleared its bar)
  std::vector<double> features;  ///< empty when not finished
  double bar_m = 0.0;            ///< the bar the trial reached (0 when not finished)
  std::string technique;         ///< nearest captured technique ("" when unknown)
  /// The second feature set's values (PoolTable::orientation; a jump's 3-D bar-frame rotation):
  /// empty when the table has none or the trial did not record it.
  std::vector<double> orientation;
};

/// A named closed interval: one parameter of the box, or one feature's declared range.
struct Range {
  std::string name;
  double low = 0.0, high = 1.0;
};

struct PoolTable {
  base::Json params_json = base::Json::array();    ///< the box, as a task describes it (`params`)
  base::Json features_json = base::Json::array();  ///< the features, as a task describes them
  std::vector<Range> box;                          ///< params_json's names and bounds, in order
  std::vector<Range> features;                     ///< features_json's names and declared ranges
  double strategy_threshold = 0.0;
  base::Json source = base::Json::object();  ///< where the rows came from (campaign, stage, database)
  std::vector<PoolRow> rows;
  /// Optional second feature set, counted beside the first (the issue's "3-D bar-frame
  /// orientation count" for jumps): {"info": the result-info pointer it was read from, "features":
  /// [...] as a task describes them, "strategy_threshold", "described_with": the task config that
  /// declares them}; null when absent.
  base::Json orientation_json = nullptr;
  std::vector<Range> orientation_features;  ///< orientation_json's features (empty when absent)
  double orientation_threshold = 0.0;

  /// Reads a table file; a malformed one is a UserError naming the file, the JSON path and value.
  static PoolTable load(const std::filesystem::path& file);
  /// Parses a table; `origin` names it in errors.
  static PoolTable parse(const base::Json& j, const std::string& origin);
  base::Json to_json() const;

  /// The table searched by its second feature set: that set as the features (its threshold as
  /// τ), the first as the second set, and only the rows that recorded it (and those that failed
  /// outright). Throws UserError when the table has no second set or no row recorded it.
  PoolTable by_orientation() const;

  /// Index of the row nearest to x (Euclidean in the box scaled to [0,1]^d; ties: the first).
  std::size_t nearest(const std::vector<double>& x) const;
  /// Per feature, the lowest and highest value of the successful rows (the reachable range); with
  /// `orientation`, of the second feature set over the successful rows that recorded it.
  void reachable(std::vector<double>& low, std::vector<double>& high, bool orientation = false) const;
};

}  // namespace podium::tasks::pool
