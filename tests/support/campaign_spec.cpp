#include "campaign_spec.h"

#include <stdexcept>

namespace podium::testing {

nlohmann::json stage_spec(const StageSpec& s) {
  nlohmann::json stage = {{"name", s.stage},
                          {"task", s.task},
                          {"preset", "smoke"},
                          {"search", {{"algorithm", s.algorithm}}},
                          {"budget", {{"trials", s.trials}}}};
  if (!s.config.is_null()) stage["config"] = s.config;
  nlohmann::json spec = {{"name", s.name},
                         {"seed", s.seed},
                         {"workers", s.workers},
                         {"retries", s.retries},
                         {"trial_timeout_s", s.trial_timeout_s},
                         {"stages", nlohmann::json::array({stage})}};
  if (!s.executor.is_null()) spec["executor"] = s.executor;
  return spec;
}

std::string submit_spec(const std::filesystem::path& dir, const nlohmann::json& spec) {
  write_file(dir / "spec.json", spec.dump());
  const auto r = run_podium({"submit", "spec.json"}, dir);
  if (r.exit_code != 0) throw std::runtime_error("podium submit failed: " + r.err);
  return r.out.substr(0, r.out.find('\n'));
}

}  // namespace podium::testing
