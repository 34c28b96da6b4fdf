#pragma once
/// K copies of an environment stepped together, the environment steps spread over worker
/// threads (the learner batches the K policy queries on the calling thread). Each copy owns its
/// generator (seeded from derive_seed(seed, i)), so results do not depend on the thread count.
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <vector>

#include "podium/learn/env.h"

namespace podium::learn {

class VecEnv {
 public:
  /// `envs` must be non-empty with equal spaces; `num_threads` ≥ 1 counts the calling thread.
  VecEnv(std::vector<std::unique_ptr<Env>> envs, int num_threads, std::uint64_t seed);
  ~VecEnv();
  VecEnv(const VecEnv&) = delete;
  VecEnv& operator=(const VecEnv&) = delete;

  std::size_t size() const { return envs_.size(); }
  const BoxSpace& observation_space() const { return observation_space_; }
  const BoxSpace& action_space() const { return action_space_; }
  int num_threads() const { return num_threads_; }

  /// Current observation of copy i (after an automatic reset when its last episode ended).
  const std::vector<double>& observation(std::size_t i) const { return observations_[i]; }
  /// Steps every copy with actions (size() × action size, row-major, in action_space()).
  /// Copies whose episode ends are reset; their results keep the final observation.
  void step(const std::vector<double>& actions);
  /// Results of the last step, one per copy.
  const StepResult& result(std::size_t i) const { return results_[i]; }

  /// Copy i's Env::start_transitions() when its current episode began after the last call for i,
  /// else none: a learner that calls this after every step() stores each start once. load_state()
  /// clears them (a restored episode's were taken before the checkpoint).
  std::span<const Transition> take_start_transitions(std::size_t i);

  /// Copy i's Env::action_scale() for its current episode.
  double action_scale(std::size_t i) const { return envs_[i]->action_scale(); }

  /// Returns of episodes finished since the last call (for learning curves).
  std::vector<double> take_finished_returns();

  /// Rollout state (environment states, current observations, running returns) for checkpoints.
  base::Json save_state() const;
  void load_state(const base::Json& state);

 private:
  void run_parallel(const std::function<void(std::size_t)>& work);
  void worker_loop(int worker);

  std::vector<std::unique_ptr<Env>> envs_;
  BoxSpace observation_space_, action_space_;
  int num_threads_;
  std::vector<std::vector<double>> observations_;
  std::vector<StepResult> results_;
  std::vector<double> running_returns_;
  std::vector<double> finished_returns_;
  std::vector<char> fresh_start_;  // copy i reset since take_start_transitions(i)

  // Persistent workers: each generation runs `work_` on the copies i ≡ worker (mod threads).
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_cv_, done_cv_;
  const std::function<void(std::size_t)>* work_ = nullptr;
  std::uint64_t generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
};

}  // namespace podium::learn
