#pragma once
// A recorded pool of trials as a table: each recorded take-off's parameters and what its trial
// gave (success, strategy feature, bar reached, nearest captured technique), exported from a
// campaign stage by export_pool.py. Searches replay over it by lookup: parameters x read as the
// recorded row nearest to x in the box scaled to [0,1]^d, so a search over a pool is restricted
// to the pool's points. README.md describes the file.
#include <filesystem>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/search/space.h"
#include "podium/search/strategies.h"

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
};

struct PoolTable {
  search::Space space;
  std::vector<search::Feature> features;
  double strategy_threshold = 0.0;
  base::Json source = base::Json::object();  ///< where the rows came from (campaign, stage, database)
  std::vector<PoolRow> rows;

  /// Reads a table file; a malformed one is a UserError naming the file, the JSON path and value.
  static PoolTable load(const std::filesystem::path& file);
  /// Parses a table; `origin` names it in errors.
  static PoolTable parse(const base::Json& j, const std::string& origin);
  base::Json to_json() const;

  /// Index of the row nearest to x (Euclidean in the box scaled to [0,1]^d; ties: the first).
  std::size_t nearest(const std::vector<double>& x) const;
  /// The lookup as strategies.h's Outcome: the nearest row's features when it succeeded.
  search::Outcome outcome() const;
  /// Per feature, the lowest and highest value of the successful rows (the reachable range).
  void reachable(std::vector<double>& low, std::vector<double>& high) const;
};

}  // namespace podium::tasks::pool
