// Slow clients cannot stall the dashboard: 64 connections each sending a request header one byte
// a second (and coming back when cut off) beside 20 ordinary requests, which must all be answered.
// How fast they are answered is bench/web_dashboard's slow-client bench (no timing bar here).
#include <gtest/gtest.h>

#include <thread>

#include "dashboard_support.h"
#include "podium/store/store.h"
#include "slow_clients.h"

namespace podium::web_dashboard {
namespace {

TEST(SlowClients, SixtyFourTricklingHeadersLeaveEveryOrdinaryRequestAnswered) {
  podium::testing::TempDir dir;
  {
    auto s = store::Store::open(dir / "podium.db", store::Store::Access::read_write);
    store::NewStage stage{"s", "landscape", "random"};
    stage.budget_trials = 1;
    s->add_campaign("c", base::Json::object(), 1, "", {stage});
  }
  testing::RunningServer server(dir / "podium.db");
  testing::SlowClientLoad load;  // 64 connections, a byte a second, 20 GETs of /api/campaigns
  const auto run = testing::run_slow_clients(server.port(), load);
  EXPECT_EQ(run.answered, 20);
  EXPECT_EQ(run.latencies_ms.size(), 20u);
  EXPECT_GE(run.slow_opened, 64);
}

// A peer address holds at most connections_per_client connections; beyond it, the connection
// that has waited longest for a header makes room, so a fresh request is still answered.
TEST(SlowClients, ConnectionsBeyondThePerClientBoundEvictTheLongestWaiting) {
  podium::testing::TempDir dir;
  {
    auto s = store::Store::open(dir / "podium.db", store::Store::Access::read_write);
    store::NewStage stage{"s", "landscape", "random"};
    stage.budget_trials = 1;
    s->add_campaign("c", base::Json::object(), 1, "", {stage});
  }
  ServeOptions options;
  options.database = dir / "podium.db";
  options.port = 0;
  options.static_dir = PODIUM_TEST_WEB_DIR;
  options.header_timeout_s = 600;  // only the bound closes connections here
  options.connections_per_client = 8;
  Server server(options);
  const int port = server.bind();
  std::thread thread([&] { server.run(); });
  testing::SlowClientLoad load;
  load.slow_connections = 8;
  load.byte_interval_s = 0.2;
  load.requests = 5;
  load.settle_s = 0.5;
  const auto run = testing::run_slow_clients(port, load);
  server.stop();
  thread.join();
  EXPECT_EQ(run.answered, 5);
  // Without room made, each GET would have been the 9th connection and refused with 503.
  EXPECT_GT(run.slow_refused, 0);
}

}  // namespace
}  // namespace podium::web_dashboard
