#pragma once
/// The scheduler: runs queued and resumable campaigns with an executor until none is left (or,
/// with `follow`, keeps waiting for new ones). It is the only writer of trial data.
///
/// Every step is one transaction: proposals asked from a search are stored with the search's
/// state; a finished attempt is stored with its result, the tell, and the new search state. So
/// after a kill -9 at any moment the next run continues exactly: attempts that were running
/// become `interrupted` and run again, no finished trial is lost or finished twice, and the
/// search proposes what an uninterrupted run would have.
#include <cstddef>
#include <filesystem>

namespace podium::store {
class Store;
}

namespace podium::orchestrator {

struct SchedulerOptions {
  std::size_t workers = 2;                 ///< worker processes in the local pool
  bool follow = false;                     ///< keep waiting for new campaigns
  bool log_json = false;                   ///< machine-readable events on stdout
  bool progress = false;                   ///< live progress lines on stderr (a terminal)
  std::filesystem::path worker_binary;     ///< the `podium` binary that runs `podium worker`
  std::filesystem::path database;          ///< for default run folders and the lock file
};

/// Returns when no campaign is left to run (or on SIGINT/SIGTERM, after which running attempts
/// are recorded as interrupted). Throws base::RuntimeError if another scheduler holds the lock.
void run_scheduler(store::Store& store, const SchedulerOptions& options);

}  // namespace podium::orchestrator
