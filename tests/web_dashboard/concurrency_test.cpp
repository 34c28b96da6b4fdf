// The dashboard must not slow or lock a running scheduler (DESIGN.md "Store"): a 2,000-trial
// landscape campaign runs while a client hammers the API of `podium serve` on the same database.
// Each round runs it without and with the hammering client, in alternating order; zero "database
// is locked" (or any other error) on either side, and the median paired drop is under 20%.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include "campaign_spec.h"
#include "dashboard_support.h"

namespace podium::web_dashboard {
namespace {

namespace fs = std::filesystem;
using base::Json;
using Clock = std::chrono::steady_clock;

constexpr int kTrials = 2000, kRounds = 5;

struct Hammer {
  std::int64_t requests = 0, errors = 0, locked = 0;
};

// Requests the endpoints a dashboard uses, back to back on one connection, until stop is set.
Hammer hammer(int port, const std::atomic<bool>& stop) {
  Hammer h;
  httplib::Client client("127.0.0.1", port);
  client.set_keep_alive(true);
  const std::vector<std::string> paths = {"/api/version", "/api/campaigns", "/api/campaigns/1",
                                          "/api/campaigns/1/trials?limit=100&order=objective&desc=1",
                                          "/api/campaigns/1/points", "/api/campaigns/1/strategies",
                                          "/api/trials/1", "/api/trials/1/metrics"};
  for (std::size_t i = 0; !stop; ++i) {
    const auto r = client.Get(paths[i % paths.size()].c_str());
    ++h.requests;
    if (!r || r->status >= 500) ++h.errors;  // 404 is fine: trial 1 appears only after the first ask
    if (r && r->body.find("locked") != std::string::npos) ++h.locked;
  }
  return h;
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

// One campaign in a fresh database; with `hammered`, podium serve and the client run throughout.
// Returns trials per second of the scheduler run.
double run_once(bool hammered, Hammer* totals) {
  podium::testing::TempDir dir;
  podium::testing::submit_spec(dir.path(), testing::landscape_spec("load", kTrials, {{"artifact", false}}));
  pid_t serve = 0;
  std::atomic<bool> stop = false;
  std::thread client;
  Hammer h;
  if (hammered) {
    fs::create_directories(dir / "serve");
    serve = podium::testing::spawn_podium({"serve", "--db", (dir / "podium.db").string(), "--port", "0"}, dir / "serve");
    const int port = read_port(dir / "serve" / "spawn.out");
    EXPECT_GT(port, 0);
    client = std::thread([&] { h = hammer(port, stop); });
  }
  const auto start = Clock::now();
  const auto run = podium::testing::run_podium({"run", "--workers", "2", "--log-json"}, dir.path());
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (hammered) {
    stop = true;
    client.join();
    ::kill(serve, SIGTERM);
    EXPECT_EQ(podium::testing::wait_process(serve), 0);
    totals->requests += h.requests;
    totals->errors += h.errors;
    totals->locked += h.locked;
  }
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err.find("locked"), std::string::npos) << run.err;
  EXPECT_EQ(run.out.find("locked"), std::string::npos);
  const auto status = podium::testing::run_podium({"status", "1", "--json"}, dir.path());
  EXPECT_EQ(Json::parse(status.out)["done"], kTrials);
  return kTrials / seconds;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

TEST(Concurrency, HammeredApiNeitherLocksNorSlowsA2000TrialCampaign) {
  std::vector<double> alone, hammered, ratios;
  Hammer totals;
  for (int round = 0; round < kRounds; ++round) {
    // Alternating which goes first keeps slow drifts of a shared machine out of the comparison.
    if (round % 2 == 0) alone.push_back(run_once(false, &totals));
    hammered.push_back(run_once(true, &totals));
    if (round % 2 == 1) alone.push_back(run_once(false, &totals));
    ratios.push_back(hammered.back() / alone.back());
    std::printf("round %d: alone %.0f trials/s, hammered %.0f trials/s (%.1f%%)\n", round, alone.back(), hammered.back(),
                100 * (ratios.back() - 1));
  }
  // Paired within a round: the machine's throughput drifts across rounds (seen: 2100 → 1300
  // trials/s alone over 15 s), which unpaired medians would mistake for the client's effect.
  const double drop = 1.0 - median(ratios);
  std::printf("median: alone %.0f trials/s, hammered %.0f trials/s; median paired drop %.1f%%; %lld API requests, %lld errors, "
              "%lld 'locked'\n",
              median(alone), median(hammered), 100 * drop, static_cast<long long>(totals.requests),
              static_cast<long long>(totals.errors), static_cast<long long>(totals.locked));
  EXPECT_EQ(totals.locked, 0);
  EXPECT_EQ(totals.errors, 0);
  EXPECT_GT(totals.requests, 100);
  EXPECT_LT(drop, 0.20);
}

}  // namespace
}  // namespace podium::web_dashboard
