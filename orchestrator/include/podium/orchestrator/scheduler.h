#pragma once
/// The scheduler: runs queued and resumable campaigns with an executor until none is left (or,
/// with `follow`, keeps waiting for new ones). It is the only writer of trial data.
///
/// Every step is one transaction: proposals asked from a search are stored with the search's
/// state; a finished attempt is stored with its result, the tell, and the new search state. So
/// after a kill -9 at any moment the next run continues exactly: attempts that were running
/// become `interrupted` and run again, no finished trial is lost or finished twice, and the
/// search proposes what an uninterrupted run would have. Results are told to the search in the
/// order their trials were asked, and it is asked whenever fewer than the spec's `workers` trials
/// are untold, so its proposals depend on the spec alone, never on trial durations, completion
/// order or the number of worker processes. A stage's hand-over (its inputs) is
/// selected when the stage starts and stored with it, so a resumed stage hands over the same
/// trials. A stage none of whose trials succeeded ends failed with the reason, and its campaign
/// with it.
#include <cstddef>
#include <filesystem>

namespace podium::store {
class Store;
}

namespace podium::orchestrator {

struct SchedulerOptions {
  std::size_t workers = 2;              ///< worker processes in the local pool
  bool follow = false;                  ///< keep waiting for new campaigns
  bool log_json = false;                ///< machine-readable events on stdout
  bool progress = false;                ///< live progress lines on stderr (a terminal)
  std::filesystem::path worker_binary;  ///< the `podium` binary that runs `podium worker`
  std::filesystem::path database;       ///< for default run folders and the writer lock
};

/// Runs until no campaign is left to run and returns 0. On SIGINT/SIGTERM it stops at once: the
/// local workers are killed, their running attempts recorded `interrupted` (run again by the
/// next `podium run`; batch jobs live on and are re-attached), and it returns 128 + the signal
/// number if a campaign was left unfinished (0 if none was). The caller holds the database's
/// store::WriterLock (taken before the store is opened for writing).
int run_scheduler(store::Store& store, const SchedulerOptions& options);

}  // namespace podium::orchestrator
