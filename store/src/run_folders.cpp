#include "podium/store/run_folders.h"

namespace podium::store {

namespace fs = std::filesystem;

fs::path campaign_run_dir(const fs::path& database, const CampaignRecord& campaign) {
  if (!campaign.run_dir.empty()) return (fs::absolute(database).parent_path() / campaign.run_dir).lexically_normal();
  return fs::absolute(database).string() + ".runs/" + std::to_string(campaign.id);
}

std::string stage_folder_name(int index, const std::string& name) {
  constexpr std::size_t kMaxName = 64;
  std::string safe;
  for (const char ch : name.substr(0, kMaxName)) {
    const bool keep =
        (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '.' || ch == '_' || ch == '-';
    safe += keep ? ch : '_';
  }
  return "stage-" + std::to_string(index) + "-" + safe;
}

fs::path trial_folder(const fs::path& run_dir, const StageRecord& stage, std::int64_t trial_index) {
  return run_dir / stage_folder_name(stage.index, stage.name) / ("trial-" + std::to_string(trial_index));
}

}  // namespace podium::store
