#pragma once
// Runs an external program (sbatch, squeue, scancel, sinfo) without a shell and captures its
// output: arguments are passed as they are, never interpreted.
#include <string>
#include <vector>

namespace podium::orchestrator {

struct CommandOutput {
  int exit_code = -1;  ///< -1 when the program could not be started or was killed
  std::string out, err;
};

CommandOutput run_command(const std::vector<std::string>& argv);

/// True if `program` is found on PATH.
bool on_path(const std::string& program);

}  // namespace podium::orchestrator
