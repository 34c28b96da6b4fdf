#pragma once
/// Campaign-level operations behind the CLI: submit, control, export.
#include <cstdint>
#include <filesystem>
#include <string>

#include "podium/base/json.h"

namespace podium::store {
class Store;
struct CampaignRecord;
}  // namespace podium::store

namespace podium::orchestrator {

/// Validates a spec (including each stage's task, preset, config and search config, asked of the
/// plugin in a separate worker process) and queues it. Returns the campaign id. Throws
/// base::UserError for spec errors; the database is untouched unless the whole spec is valid.
std::int64_t submit_campaign(store::Store& store, const base::Json& spec, const std::string& source,
                             const std::filesystem::path& worker_binary);

/// pause: stop starting trials; resume: queue again; cancel: stop running trials, end the campaign.
/// Throws base::UserError if the campaign is in a state the action does not apply to.
void control_campaign(store::Store& store, const std::string& id_or_name, const std::string& action);

/// The folder where a campaign's trials write (spec run_dir, or <database>.runs/<id>).
std::filesystem::path campaign_run_dir(const std::filesystem::path& database, const store::CampaignRecord& campaign);

/// Every trial of a campaign as CSV (a header row, then one row per trial) or a JSON array.
std::string export_campaign(const store::Store& store, std::int64_t campaign_id, const std::string& format);

}  // namespace podium::orchestrator
