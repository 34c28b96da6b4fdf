#include "podium/plugins/loader.h"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cstdlib>
#include <sstream>

#include "podium/base/error.h"
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

std::shared_ptr<Task> load_task(const std::string& task_name) {
  const auto folders = plugin_search_path();
  for (const auto& folder : folders) {
    const fs::path candidate = folder / file_name_for(task_name);
    if (fs::exists(candidate)) return load_task_file(candidate, task_name);
  }
  std::string searched;
  for (const auto& f : folders) searched += (searched.empty() ? "" : ":") + f.string();
  throw UserError("plugin \"" + task_name + "\": no file " + file_name_for(task_name) + " in " + searched +
                  " (set PODIUM_PLUGIN_PATH)");
}

std::shared_ptr<Task> load_task_file(const fs::path& file, const std::string& task_name) {
  auto library = std::make_shared<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  library->load(file.string(), boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local, ec);
  if (ec) throw UserError(file.string() + ": cannot load plugin: " + ec.message());
  for (const char* symbol : {"podium_task_descriptor", "podium_create_task", "podium_destroy_task"})
    if (!library->has(symbol))
      throw UserError(file.string() + ": not a Podium task plugin (missing symbol " + symbol + ")");

  const auto& descriptor = library->get_alias<const TaskDescriptor>("podium_task_descriptor");
  if (descriptor.abi_version != kAbiVersion)
    throw UserError(file.string() + ": plugin ABI version " + std::to_string(descriptor.abi_version) +
                    " (built with Podium " + descriptor.podium_version + ", " + descriptor.compiler +
                    ") but this host accepts ABI version " + std::to_string(kAbiVersion) +
                    " (Podium " + base::version() + "); rebuild the plugin");
  if (task_name != descriptor.task_name)
    throw UserError(file.string() + ": plugin declares task \"" + descriptor.task_name + "\", expected \"" +
                    task_name + "\"");

  auto& create = library->get_alias<CreateTaskFn>("podium_create_task");
  auto& destroy = library->get_alias<DestroyTaskFn>("podium_destroy_task");
  Task* raw = create();
  // The deleter holds the library, so it stays loaded while the task lives.
  return std::shared_ptr<Task>(raw, [library, &destroy](Task* t) { destroy(t); });
}

}  // namespace podium::plugins
