// The dashboard must not lock a running scheduler (docs/architecture.md "The store contract"): a 2,000-trial landscape
// campaign runs while a client hammers the API of `podium serve` on the same database; zero
// "database is locked" (or any other error) on either side. Its effect on throughput is measured
// by bench/web_dashboard's concurrency bench, not here (the suite holds no timing threshold).
#include <gtest/gtest.h>

#include <cstdio>

#include "concurrency_load.h"

namespace podium::web_dashboard {
namespace {

TEST(Concurrency, HammeredApiNeverLocksA2000TrialCampaign) {
  for (int round = 0; round < 2; ++round) {
    const auto run = testing::run_landscape_load(2000, true);
    std::printf("round %d: %.0f trials/s, %lld API requests, %lld errors, %lld 'locked'\n", round, run.trials_per_second,
                static_cast<long long>(run.requests), static_cast<long long>(run.errors), static_cast<long long>(run.locked));
    EXPECT_TRUE(run.ok) << run.problem;
    EXPECT_EQ(run.locked, 0);
    EXPECT_EQ(run.errors, 0);
    EXPECT_GT(run.requests, 100);
  }
}

}  // namespace
}  // namespace podium::web_dashboard
