#include "finished_campaign.h"

#include <stdexcept>

#include "campaign_spec.h"

namespace podium::testing {

std::set<std::string> FinishedCampaign::artifact_names(const store::TrialRecord& trial) const {
  std::set<std::string> names;
  for (const auto& a : store->artifacts(trial.id)) names.insert(a.name);
  return names;
}

std::set<std::string> FinishedCampaign::metric_names(const store::TrialRecord& trial) const {
  std::set<std::string> names;
  for (const auto& m : store->metrics(trial.id)) names.insert(m.name);
  return names;
}

FinishedCampaign run_campaign_to_end(const std::filesystem::path& dir, const nlohmann::json& spec) {
  FinishedCampaign c;
  c.id = std::stoll(submit_spec(dir, spec));
  const auto run = run_podium({"run"}, dir);
  if (run.exit_code != 0) throw std::runtime_error("podium run exited " + std::to_string(run.exit_code) + ": " + run.err);
  c.store = store::Store::open(dir / "podium.db", store::Store::Access::read_only);
  for (const auto& stage : c.store->stages(c.id)) {
    if (stage.state != "done") throw std::runtime_error("stage " + stage.name + " is " + stage.state + ": " + stage.error);
    auto& trials = c.trials[stage.name] = c.store->trials(stage.id);
    for (const auto& t : trials)
      if (t.state != "done")
        throw std::runtime_error("trial " + stage.name + "/" + std::to_string(t.index) + " is " + t.state + ": " + t.error);
  }
  return c;
}

}  // namespace podium::testing
