#pragma once
/// The style-curve get-up's command-line tool, `podium tool getup_curves COMMAND ...` (curve get-up
/// seed §4.1, §4.3, Fig. 8): `extract` a curve from a clip, `edit` a curve file (rise time, T, a
/// control point), `stats` of labelled clips by strategy. docs/tasks/getup_curves.md "Tool".
#include <ostream>
#include <string>
#include <vector>

#include "podium/plugins/task.h"

namespace podium::tasks::getup_curves {

/// extract, edit, stats.
std::vector<plugins::ToolCommand> curve_tool_commands();

/// Runs one command (args[0]); returns the exit code: 0 done, 2 bad usage or input (one line on
/// `err`), 1 another failure.
int run_curve_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace podium::tasks::getup_curves
