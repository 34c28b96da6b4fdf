#pragma once
// One landscape campaign run by the real CLI in a fresh database, optionally while `podium serve`
// on the same file answers a client that requests the dashboard's endpoints back to back. Shared
// by the load test (no errors, no "database is locked") and the concurrency bench (throughput).
#include <cstdint>
#include <string>

namespace podium::web_dashboard::testing {

struct LoadRun {
  bool ok = false;                                    ///< the campaign finished with every trial done and no "locked" output
  std::string problem;                                ///< what went wrong, when !ok
  double trials_per_second = 0.0;                     ///< of the scheduler run
  std::int64_t requests = 0, errors = 0, locked = 0;  ///< the client's (hammered runs only)
};

LoadRun run_landscape_load(int trials, bool hammered);

}  // namespace podium::web_dashboard::testing
