#pragma once
// Names of the folders the scheduler makes in a campaign's run folder. A spec's names never reach
// the filesystem as they are: a stage named "x/../../ESCAPED" must stay inside the run folder.
#include <string>

namespace podium::orchestrator {

/// "stage-<index>-<name>" with every byte of the name outside [A-Za-z0-9._-] replaced by '_' and
/// the name cut to 64 bytes: one path component, unique by its index, still readable.
std::string stage_folder_name(int index, const std::string& name);

}  // namespace podium::orchestrator
