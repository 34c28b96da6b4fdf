#include "batch_trial.h"

#include <fstream>

namespace podium::testing {

namespace fs = std::filesystem;
using nlohmann::json;

json order_json(const TrialOrder& o) {
  return {{"key", 1},
          {"task", o.task},
          {"config", o.config},
          {"params", o.params},
          {"context", json::object()},
          {"inputs", o.inputs},
          {"previous_attempt", o.previous_attempt},
          {"seed", o.seed},
          {"trial_index", 0},
          {"attempt", o.attempt},
          {"work_dir", o.work_dir.string()}};
}

BatchTrial run_batch_trial(const json& order, const fs::path& attempt_dir) {
  fs::create_directories(attempt_dir);
  write_file(attempt_dir / "order.json", order.dump());
  write_file(attempt_dir / "batch.txt", (attempt_dir / "order.json").string() + "\n");
  BatchTrial trial;
  trial.run = run_podium({"trial", "--batch", (attempt_dir / "batch.txt").string()}, attempt_dir);
  if (std::ifstream in(attempt_dir / "result.json"); in) trial.result = json::parse(in);
  std::ifstream metrics(attempt_dir / "metrics.jsonl");
  for (std::string line; std::getline(metrics, line);) trial.metrics.push_back(json::parse(line));
  return trial;
}

}  // namespace podium::testing
