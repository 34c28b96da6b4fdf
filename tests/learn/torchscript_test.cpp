// TorchScript export: Debian's python3-torch loads the exported deterministic policy and gives
// the same actions as the C++ policy for 100 random observations.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include <unistd.h>

#include "podium/base/json.h"
#include "podium/base/rng.h"
#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

namespace podium::learn {
namespace {

namespace fs = std::filesystem;

bool python_has_torch() {
  const std::string cmd = std::string(PODIUM_SYSTEM_PYTHON) + " -c 'import torch' > /dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

void check_export(Learner& learner, const std::string& name) {
  if (!python_has_torch()) GTEST_SKIP() << PODIUM_SYSTEM_PYTHON << " cannot import torch (install python3-torch)";
  const fs::path dir = fs::temp_directory_path() / ("podium_learn_ts_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
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

VecEnv pendulums(std::uint64_t seed) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < 2; ++i) envs.push_back(std::make_unique<Pendulum>());
  return VecEnv(std::move(envs), 1, seed);
}

TEST(TorchScript, PpoPolicyWithNormalizerGivesSameActionsInPython) {
  Pendulum probe;
  PpoConfig c;
  c.rollout_steps = 100;
  Ppo ppo(c, probe.observation_space(), probe.action_space(), 1);
  auto envs = pendulums(1);
  ppo.train_until(envs, 400);  // moves the normaliser and the weights away from their start
  check_export(ppo, "ppo");
}

TEST(TorchScript, SacPolicyWithBoundGivesSameActionsInPython) {
  Pendulum probe;
  SacConfig c;
  c.warmup_steps = 100;
  c.batch_size = 32;
  c.normalize_observations = true;
  Sac sac(c, probe.observation_space(), probe.action_space(), 2);
  auto envs = pendulums(2);
  sac.train_until(envs, 300);
  sac.set_action_bound(0.6);
  check_export(sac, "sac");
}

}  // namespace
}  // namespace podium::learn
