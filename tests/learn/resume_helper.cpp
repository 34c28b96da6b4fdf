// Child process of resume_test.cpp: trains a small PPO or SAC on pendulums (single-threaded).
// Usage: learn_resume_helper ppo|sac STEPS [--load CKPT] [--save CKPT] [--params FILE]
//                                          [--checkpoint FILE --stats FILE]
// --load/--save: one checkpoint before/after training. --checkpoint: a TrainingCheckpoint every
// 3 updates, resumed when present (the SIGKILL test), with one line per update appended to
// --stats ("update env_steps episodes mean_return").
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include "podium/learn/classic_control.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"
#include "podium/learn/training_checkpoint.h"

using namespace podium::learn;

int main(int argc, char** argv) {
  if (argc < 3) return 2;
  const std::string algo = argv[1];
  const std::int64_t steps = std::atoll(argv[2]);
  std::string load, save, params, checkpoint_file, stats_file;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--load")) load = argv[i + 1];
    if (!std::strcmp(argv[i], "--save")) save = argv[i + 1];
    if (!std::strcmp(argv[i], "--params")) params = argv[i + 1];
    if (!std::strcmp(argv[i], "--checkpoint")) checkpoint_file = argv[i + 1];
    if (!std::strcmp(argv[i], "--stats")) stats_file = argv[i + 1];
  }
  std::vector<std::unique_ptr<Env>> copies;
  for (int i = 0; i < 3; ++i) copies.push_back(std::make_unique<Pendulum>());
  VecEnv envs(std::move(copies), 1, 17);
  Pendulum probe;
  std::unique_ptr<Learner> learner;
  if (algo == "ppo") {
    PpoConfig c;
    c.rollout_steps = 50;  // iterations of 150 steps, not aligned with the 200-step episodes
    c.minibatch_size = 32;
    c.epochs = 2;
    c.sigma_anneal_steps = c.lr_anneal_steps = 1000;
    c.policy_lr_end = 1e-4;
    learner = std::make_unique<Ppo>(c, probe.observation_space(), probe.action_space(), 5);
  } else {
    SacConfig c;
    c.warmup_steps = 150;
    c.batch_size = 32;
    c.buffer_capacity = 400;  // small enough to wrap around before the checkpoint
    c.normalize_observations = true;
    c.log_interval_steps = 60;
    auto sac = std::make_unique<Sac>(c, probe.observation_space(), probe.action_space(), 5);
    sac->set_action_bound(0.8);
    learner = std::move(sac);
  }
  if (!load.empty()) learner->load_checkpoint(load, envs);
  if (checkpoint_file.empty()) {
    learner->train_until(envs, steps);
  } else {
    TrainingCheckpoint checkpoint(checkpoint_file, 3);
    checkpoint.resume(*learner, envs);
    std::ofstream stats(stats_file, std::ios::app);
    learner->train_until(envs, steps, [&](const TrainStats& s) {
      stats << checkpoint.updates() + 1 << ' ' << s.env_steps << ' ' << s.episodes << ' ' << std::hexfloat << s.mean_return
            << std::defaultfloat << std::endl;  // hexfloat: the exact value
      checkpoint.on_update(*learner, envs, nullptr);
    });
  }
  if (!save.empty()) learner->save_checkpoint(save, envs);
  if (!params.empty()) {
    const auto p = learner->parameters();
    std::ofstream out(params, std::ios::binary);
    out.write(reinterpret_cast<const char*>(p.data()), std::streamsize(p.size() * sizeof(float)));
  }
  return 0;
}
