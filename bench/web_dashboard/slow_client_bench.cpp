// Slow clients against `podium serve`: N connections each send a request header one byte per
// interval (reconnecting when cut off), while ordinary GETs of /api/campaigns are made one after
// another on fresh connections. Prints each GET's latency and p50/p95/max.
// Target: 64 slow connections at one byte a second, 20 of 20 GETs answered, each within 1 s.
// Usage: web_dashboard_slow_client_bench [--slow N] [--requests N] [--interval S] [--header-timeout S]
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "bench_args.h"
#include "podium/store/store.h"
#include "podium/web_dashboard/server.h"
#include "slow_clients.h"

namespace fs = std::filesystem;
using podium::base::Json;

int main(int argc, char** argv) {
  podium::web_dashboard::testing::SlowClientLoad load;
  double header_timeout_s = 5.0;
  if (!podium::bench::read_flags(
          argc, argv, "[--slow N ≥ 0] [--requests N ≥ 1] [--interval S > 0] [--header-timeout S > 0]",
          [&](const std::string& key, const char* value) {
            if (key == "--slow") return podium::bench::checked(podium::bench::count(value, 0, 100'000, load.slow_connections));
            if (key == "--requests") return podium::bench::checked(podium::bench::count(value, 1, 1'000'000, load.requests));
            if (key == "--interval")
              return podium::bench::checked(podium::bench::real_number(value, load.byte_interval_s) && load.byte_interval_s > 0);
            if (key == "--header-timeout")
              return podium::bench::checked(podium::bench::real_number(value, header_timeout_s) && header_timeout_s > 0);
            return podium::bench::Flag::unknown;
          }))
    return 2;
  const fs::path dir = fs::temp_directory_path() / ("podium-slow-client-bench-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    auto store = podium::store::Store::open(dir / "bench.db", podium::store::Store::Access::read_write);
    podium::store::NewStage stage{"explore", "landscape", "random"};
    stage.budget_trials = 1;
    store->add_campaign("slow-client-bench", Json::object(), 1, "", {stage});
  }
  podium::web_dashboard::ServeOptions options;
  options.database = dir / "bench.db";
  options.port = 0;
  options.static_dir = PODIUM_WEB_DIR;
  options.header_timeout_s = header_timeout_s;
  podium::web_dashboard::Server server(options);
  const int port = server.bind();
  std::thread thread([&] { server.run(); });
  const auto run = podium::web_dashboard::testing::run_slow_clients(port, load);
  server.stop();
  thread.join();
  fs::remove_all(dir);
  std::printf("%d slow connections (one header byte every %.2f s, header deadline %.1f s; %d opened, %d cut off)\n",
              load.slow_connections, load.byte_interval_s, header_timeout_s, run.slow_opened, run.slow_refused);
  std::printf("GET %s, one after another:", load.path.c_str());
  for (const double ms : run.latencies_ms) std::printf(" %.1f", ms);
  std::printf(" ms\n");
  auto sorted = run.latencies_ms;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))];
  };
  const bool pass = run.answered == load.requests && sorted.back() < 1000.0;
  std::printf("answered %d of %d; p50 %.1f ms, p95 %.1f ms, max %.1f ms; %s (all answered, each within 1 s)\n", run.answered,
              load.requests, at(0.5), at(0.95), sorted.back(), pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
