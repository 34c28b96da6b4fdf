#pragma once
// The files one Slurm attempt shares with the scheduler through the campaign's run folder:
// order.json (written by the scheduler), metrics.jsonl (appended by the job), result.json
// (written by the job atomically: temporary file + rename, so a half-written result is never read).
#include <filesystem>

namespace podium::orchestrator {

class SlurmAttemptFiles {
 public:
  explicit SlurmAttemptFiles(std::filesystem::path folder) : folder_(std::move(folder)) {}
  const std::filesystem::path& folder() const { return folder_; }
  std::filesystem::path order() const { return folder_ / "order.json"; }
  std::filesystem::path metrics() const { return folder_ / "metrics.jsonl"; }
  std::filesystem::path result() const { return folder_ / "result.json"; }

 private:
  std::filesystem::path folder_;
};

}  // namespace podium::orchestrator
