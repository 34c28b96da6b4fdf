#include "task_tools.h"

#include <algorithm>
#include <iomanip>

#include "podium/base/error.h"
#include "podium/base/suggest.h"
#include "podium/plugins/loader.h"

namespace podium::orchestrator {

namespace {

constexpr const char* kToolUsage =
    R"(usage: podium tool [--all]              installed tasks that have tools (--all: with the test plugins)
       podium tool TASK [--help]          TASK's commands
       podium tool TASK COMMAND [ARGS...] runs a command (COMMAND --help: its options)
)";

std::vector<std::string> command_names(const std::vector<plugins::ToolCommand>& commands) {
  std::vector<std::string> names;
  for (const auto& c : commands) names.push_back(c.name);
  return names;
}

int list_tool_tasks(bool with_test_plugins, std::ostream& out, std::ostream& err) {
  int listed = 0;
  for (const auto& [name, file] : plugins::installed_plugins()) {
    if (!with_test_plugins && plugins::is_test_plugin(file)) continue;
    try {
      const auto commands = plugins::load_task_file(file, name)->tools();
      if (commands.empty()) continue;
      out << std::left << std::setw(16) << name << " " << base::name_list(command_names(commands)) << "\n";
      ++listed;
    } catch (const std::exception& e) {
      err << "podium tool: " << name << ": cannot be loaded: " << e.what() << "\n";
    }
  }
  if (listed == 0) out << "no installed task has tools\n";
  else out << "(podium tool TASK --help: a task's commands)\n";
  return 0;
}

void list_commands(const std::string& task, const std::vector<plugins::ToolCommand>& commands, std::ostream& out) {
  out << "usage: podium tool " << task << " COMMAND [ARGS...]   (COMMAND --help: its options)\n\ncommands:\n";
  for (const auto& c : commands) {
    out << "  " << c.name << " " << c.synopsis << "\n";
    out << "      " << c.summary << "\n";
  }
}

}  // namespace

int run_task_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  if (args.empty() || args[0] == "--all") {
    if (args.size() > 1) {
      err << "podium tool: unexpected argument \"" << args[1] << "\"\n" << kToolUsage;
      return 2;
    }
    return list_tool_tasks(!args.empty(), out, err);
  }
  if (args[0] == "--help" || args[0] == "-h") {
    out << kToolUsage;
    return 0;
  }
  if (args[0].starts_with("-")) {
    err << "podium tool: unknown option \"" << args[0] << "\"\n" << kToolUsage;
    return 2;
  }
  const std::string& task_name = args[0];
  const auto task = plugins::load_task(task_name);  // a missing plugin: base::UserError, one line
  const auto commands = task->tools();
  if (commands.empty()) {
    err << "podium tool: task \"" << task_name << "\" has no tools\n";
    return 2;
  }
  if (args.size() == 1 || args[1] == "--help" || args[1] == "-h") {
    list_commands(task_name, commands, out);
    return 0;
  }
  const std::vector<std::string> names = command_names(commands);
  if (std::find(names.begin(), names.end(), args[1]) == names.end()) {
    err << "podium tool " << task_name << ": no command \"" << args[1] << "\"" << base::did_you_mean(args[1], names)
        << "; commands: " << base::name_list(names) << "\n";
    return 2;
  }
  return task->tool(std::vector<std::string>(args.begin() + 1, args.end()), out, err);
}

}  // namespace podium::orchestrator
