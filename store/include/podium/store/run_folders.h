#pragma once
/// Where a campaign's trials keep their files. The scheduler makes these folders, the CLI and the
/// dashboard read them: one rule for all, so they cannot disagree. A spec's names never reach the
/// filesystem as they are: a stage named "x/../../ESCAPED" stays inside the run folder.
#include <cstdint>
#include <filesystem>
#include <string>

#include "podium/store/store.h"

namespace podium::store {

/// The campaign's run folder: its spec's run_dir (stored absolute by submit; one stored relative
/// by an older podium is relative to the database), else <database>.runs/<campaign id>.
std::filesystem::path campaign_run_dir(const std::filesystem::path& database, const CampaignRecord& campaign);

/// "stage-<index>-<name>" with every byte of the name outside [A-Za-z0-9._-] replaced by '_' and
/// the name cut to 64 bytes: one path component, unique by its index, still readable.
std::string stage_folder_name(int index, const std::string& name);

/// A trial's work folder, kept across its attempts: <run folder>/<stage folder>/trial-<index>.
std::filesystem::path trial_folder(const std::filesystem::path& run_dir, const StageRecord& stage, std::int64_t trial_index);

/// The file in a trial's folder that keeps what its attempts wrote to stderr, appended.
inline constexpr const char* kTrialLog = "trial.log";

}  // namespace podium::store
