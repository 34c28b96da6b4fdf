#include "concurrency_load.h"

#include <httplib.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>
#include <vector>

#include "campaign_spec.h"
#include "dashboard_support.h"

namespace podium::web_dashboard::testing {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Requests the endpoints a dashboard uses, back to back on one connection, until stop is set.
void hammer(int port, const std::atomic<bool>& stop, LoadRun& out) {
  httplib::Client client("127.0.0.1", port);
  client.set_keep_alive(true);
  const std::vector<std::string> paths = {"/api/version",
                                          "/api/campaigns",
                                          "/api/campaigns/1",
                                          "/api/campaigns/1/trials?limit=100&order=objective&desc=1",
                                          "/api/campaigns/1/points",
                                          "/api/campaigns/1/strategies",
                                          "/api/trials/1",
                                          "/api/trials/1/metrics"};
  for (std::size_t i = 0; !stop; ++i) {
    const auto r = client.Get(paths[i % paths.size()].c_str());
    ++out.requests;
    if (!r || r->status >= 500) ++out.errors;  // 404 is fine: trial 1 appears only after the first ask
    if (r && r->body.find("locked") != std::string::npos) ++out.locked;
  }
}

int read_port(const fs::path& out) {
  for (int i = 0; i < 400; ++i) {
    std::ifstream in(out);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (const auto at = text.find("http://127.0.0.1:"); at != std::string::npos) return std::stoi(text.substr(at + 17));
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  return 0;
}

}  // namespace

LoadRun run_landscape_load(int trials, bool hammered) {
  LoadRun result;
  podium::testing::TempDir dir;
  podium::testing::submit_spec(dir.path(), landscape_spec("load", trials, {{"artifact", false}}));
  pid_t serve = 0;
  std::atomic<bool> stop = false;
  std::thread client;
  if (hammered) {
    fs::create_directories(dir / "serve");
    serve = podium::testing::spawn_podium({"serve", "--db", (dir / "podium.db").string(), "--port", "0"}, dir / "serve");
    const int port = read_port(dir / "serve" / "spawn.out");
    if (port == 0) {
      ::kill(serve, SIGTERM);
      podium::testing::wait_process(serve);
      result.problem = "podium serve printed no URL";
      return result;
    }
    client = std::thread([&] { hammer(port, stop, result); });
  }
  const auto start = Clock::now();
  const auto run = podium::testing::run_podium({"run", "--workers", "2", "--log-json"}, dir.path());
  result.trials_per_second = trials / std::chrono::duration<double>(Clock::now() - start).count();
  if (hammered) {
    stop = true;
    client.join();
    ::kill(serve, SIGTERM);
    if (podium::testing::wait_process(serve) != 0) result.problem += "podium serve did not exit cleanly; ";
  }
  if (run.exit_code != 0) result.problem += "podium run exited " + std::to_string(run.exit_code) + ": " + run.err + "; ";
  if (run.err.find("locked") != std::string::npos || run.out.find("locked") != std::string::npos)
    result.problem += "the scheduler printed 'locked'; ";
  const auto status = podium::testing::run_podium({"status", "1", "--json"}, dir.path());
  if (status.exit_code != 0 || nlohmann::json::parse(status.out)["done"] != trials)
    result.problem += "not every trial is done: " + status.out + "; ";
  result.ok = result.problem.empty();
  return result;
}

}  // namespace podium::web_dashboard::testing
