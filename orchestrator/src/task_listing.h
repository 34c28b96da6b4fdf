#pragma once
// `podium tasks [NAME] [--json] [--config JSON]`: the installed task plugins and what each declares (params,
// features, metrics, objectives, presets, and its config keys with defaults and allowed values,
// as the task's own config reader describes them).
#include <filesystem>
#include <string>

#include "podium/base/json.h"

namespace podium::orchestrator {

/// Every task plugin found in the plugin search path (the first file of a name wins; test
/// plugins only `with_test_plugins`), or only `name`, each described by a fresh worker process (`worker_binary`) with the default
/// config:
/// [{"name", "file", description keys... } or {"name", "file", "error"}]. A named task that is
/// not installed or cannot be described is a base::UserError. `config` (only with a `name`)
/// describes the task at that config instead of the default one (e.g. another stage's features); a
/// value the task rejects is a base::UserError naming `--config`'s JSON path.
base::Json list_tasks(const std::filesystem::path& worker_binary, const std::string& name = "", bool with_test_plugins = false,
                      const base::Json& config = base::Json::object());

/// The listing as text for people: one block per task.
std::string format_tasks(const base::Json& tasks);

}  // namespace podium::orchestrator
