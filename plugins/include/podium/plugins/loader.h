#pragma once
/// Finds, checks and loads task plugins (Boost.DLL).
///
/// A plugin named "landscape" is the file libpodium_task_landscape.so, searched in each folder of
/// PODIUM_PLUGIN_PATH (colon-separated), then in <bin>/../lib/podium/plugins next to the running
/// binary (the build tree mirrors the install layout). Every failure is one line:
/// a missing file (with the folders searched, the installed tasks and the nearest names), a missing symbol, or an ABI mismatch
/// saying what the library was built for and what this host accepts.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "podium/plugins/task.h"

namespace podium::plugins {

/// The folders searched, in order.
std::vector<std::filesystem::path> plugin_search_path();

/// Loads the plugin and creates its task. The returned object keeps its library loaded and is
/// destroyed by the library's own destroy function. Throws base::UserError on any failure.
std::shared_ptr<Task> load_task(const std::string& task_name);

/// Every plugin file in the search path by task name (the first file of a name wins).
std::map<std::string, std::filesystem::path> installed_plugins();

/// Whether a plugin file is a test plugin (it exports podium_test_only_task). Reads its symbol
/// table; the library is not loaded.
bool is_test_plugin(const std::filesystem::path& file);

/// Loads a plugin from an explicit file (tests, tools).
std::shared_ptr<Task> load_task_file(const std::filesystem::path& file, const std::string& task_name);

}  // namespace podium::plugins
