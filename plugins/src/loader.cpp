#include "podium/plugins/loader.h"

#include <algorithm>
#include <boost/dll/library_info.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cstdlib>
#include <sstream>

#include "podium/base/error.h"
#include "podium/base/suggest.h"
#include "podium/base/version.h"
#include "podium/plugins/export.h"

namespace podium::plugins {

namespace fs = std::filesystem;
using base::UserError;

namespace {
std::string file_name_for(const std::string& task_name) { return "libpodium_task_" + task_name + ".so"; }
}  // namespace

std::vector<fs::path> plugin_search_path() {
  std::vector<fs::path> folders;
  if (const char* env = std::getenv("PODIUM_PLUGIN_PATH")) {
    std::stringstream in(env);
    std::string item;
    while (std::getline(in, item, ':'))
      if (!item.empty()) folders.emplace_back(item);
  }
  const fs::path exe_dir = boost::dll::program_location().parent_path().string();
  folders.push_back(exe_dir.parent_path() / "lib/podium/plugins");  // build and install trees
  return folders;
}

std::map<std::string, fs::path> installed_plugins() {
  const std::string prefix = "libpodium_task_", suffix = ".so";
  std::map<std::string, fs::path> found;
  for (const auto& folder : plugin_search_path()) {
    std::error_code ec;  // a folder of the search path that does not exist holds no plugins
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      const std::string file = entry.path().filename().string();
      if (file.size() <= prefix.size() + suffix.size() || !file.starts_with(prefix) || !file.ends_with(suffix)) continue;
      found.emplace(file.substr(prefix.size(), file.size() - prefix.size() - suffix.size()), entry.path());
    }
  }
  return found;
}

bool is_test_plugin(const fs::path& file) {
  try {
    const auto symbols = boost::dll::library_info(file.string()).symbols();
    return std::find(symbols.begin(), symbols.end(), "podium_test_only_task") != symbols.end();
  } catch (const std::exception&) {
    return false;  // not an ELF file we can read: loading it will say what is wrong
  }
}

std::shared_ptr<Task> load_task(const std::string& task_name) {
  const auto folders = plugin_search_path();
  for (const auto& folder : folders) {
    const fs::path candidate = folder / file_name_for(task_name);
    if (fs::exists(candidate)) return load_task_file(candidate, task_name);
  }
  std::string searched;
  for (const auto& f : folders) searched += (searched.empty() ? "" : ":") + f.string();
  std::vector<std::string> installed;
  for (const auto& [name, file] : installed_plugins())
    if (!is_test_plugin(file)) installed.push_back(name);
  throw UserError("plugin \"" + task_name + "\": no file " + file_name_for(task_name) + " in " + searched +
                  " (set PODIUM_PLUGIN_PATH); installed tasks: " + base::name_list(installed) +
                  base::did_you_mean(task_name, installed));
}

std::shared_ptr<Task> load_task_file(const fs::path& file, const std::string& task_name) {
  auto library = std::make_shared<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  library->load(file.string(), boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local, ec);
  if (ec) throw UserError(file.string() + ": cannot load plugin: " + ec.message());
  for (const char* symbol : {"podium_task_descriptor", "podium_create_task", "podium_destroy_task"})
    if (!library->has(symbol)) throw UserError(file.string() + ": not a Podium task plugin (missing symbol " + symbol + ")");

  const auto& descriptor = library->get_alias<const TaskDescriptor>("podium_task_descriptor");
  if (descriptor.abi_version != kAbiVersion)
    throw UserError(file.string() + ": plugin ABI version " + std::to_string(descriptor.abi_version) + " (built with Podium " +
                    descriptor.podium_version + ", " + descriptor.compiler + ") but this host accepts ABI version " +
                    std::to_string(kAbiVersion) + " (Podium " + base::version() + "); rebuild the plugin");
  if (task_name != descriptor.task_name)
    throw UserError(file.string() + ": plugin declares task \"" + descriptor.task_name + "\", expected \"" + task_name + "\"");

  auto& create = library->get_alias<CreateTaskFn>("podium_create_task");
  auto& destroy = library->get_alias<DestroyTaskFn>("podium_destroy_task");
  Task* raw = create();
  // The deleter holds the library, so it stays loaded while the task lives.
  return std::shared_ptr<Task>(raw, [library, &destroy](Task* t) { destroy(t); });
}

}  // namespace podium::plugins
