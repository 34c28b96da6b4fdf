#pragma once
// `podium tool [TASK [COMMAND [ARGS...]]]`: the command-line tools task plugins ship
// (plugins::Task::tools and tool), run in the `podium` process itself.
#include <ostream>
#include <string>
#include <vector>

namespace podium::orchestrator {

/// Runs `podium tool` with `args` (what follows the word "tool"): none or --all lists the
/// installed tasks that have tools (--all: with the test plugins); TASK or TASK --help lists
/// TASK's commands; TASK COMMAND ARGS... runs the command. Returns the exit code (0 done, 2 bad
/// usage or input, 1 a failure); errors are one line on `err`.
int run_task_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace podium::orchestrator
