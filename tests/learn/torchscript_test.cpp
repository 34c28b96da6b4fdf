// TorchScript export: Debian's python3-torch loads the exported deterministic policy and gives
// the same actions as the C++ policy for 100 random observations.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "podium/base/json.h"
#include "podium/base/rng.h"
#include "small_learners.h"

namespace podium::learn {
namespace {

namespace fs = std::filesystem;

bool python_has_torch() {
  const std::string cmd = std::string(PODIUM_SYSTEM_PYTHON) + " -c 'import torch' > /dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

void check_export(Learner& learner, const std::string& name) {
  if (!python_has_torch()) GTEST_SKIP() << PODIUM_SYSTEM_PYTHON << " cannot import torch (install python3-torch)";
  const fs::path dir = testing::temp_dir("ts_" + name);
  learner.export_torchscript(dir / "policy.pt");
  base::Rng rng(3);
  base::Json cases{{"observations", base::Json::array()}, {"actions", base::Json::array()}};
  std::vector<double> action(1);
  for (int i = 0; i < 100; ++i) {
    // Wider than the pendulum's range so the normaliser's clip and the action bounds are exercised.
    std::vector<double> obs{rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-12.0, 12.0)};
    learner.act(obs, action, true);
    cases["observations"].push_back(obs);
    cases["actions"].push_back(action);
  }
  std::ofstream(dir / "cases.json") << cases.dump();
  const std::string cmd = std::string(PODIUM_SYSTEM_PYTHON) + " " + LEARN_TESTDATA_DIR + "/check_torchscript.py " +
                          (dir / "policy.pt").string() + " " + (dir / "cases.json").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  fs::remove_all(dir);
}

TEST(TorchScript, PpoPolicyWithNormalizerGivesSameActionsInPython) {
  auto envs = testing::pendulums(1);
  check_export(*testing::trained_ppo(envs, 400), "ppo");  // weights and normaliser moved from their start
}

TEST(TorchScript, SacPolicyWithBoundGivesSameActionsInPython) {
  auto envs = testing::pendulums(2);
  const auto sac = testing::trained_sac(envs, 300);
  sac->set_action_bound(0.6);
  check_export(*sac, "sac");
}

}  // namespace
}  // namespace podium::learn
