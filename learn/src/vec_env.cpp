#include "podium/learn/vec_env.h"

#include <algorithm>
#include <span>

#include "podium/base/error.h"
#include "podium/base/rng.h"

namespace podium::learn {

VecEnv::VecEnv(std::vector<std::unique_ptr<Env>> envs, int num_threads, std::uint64_t seed)
    : envs_(std::move(envs)), num_threads_(num_threads) {
  if (envs_.empty()) throw base::UserError("learn: VecEnv needs at least one environment, got 0");
  if (num_threads_ < 1) throw base::UserError("learn: VecEnv num_threads " + std::to_string(num_threads) + " is not ≥ 1");
  num_threads_ = std::min<int>(num_threads_, static_cast<int>(envs_.size()));
  observation_space_ = envs_[0]->observation_space();
  action_space_ = envs_[0]->action_space();
  const std::size_t n = envs_.size();
  observations_.resize(n);
  results_.resize(n);
  running_returns_.assign(n, 0.0);
  fresh_start_.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (envs_[i]->observation_space().size() != observation_space_.size() ||
        envs_[i]->action_space().size() != action_space_.size())
      throw base::UserError("learn: VecEnv environment " + std::to_string(i) + " has spaces of other sizes than environment 0");
    envs_[i]->seed(base::derive_seed(seed, i));
    envs_[i]->reset(observations_[i]);
  }
  for (int w = 1; w < num_threads_; ++w) workers_.emplace_back([this, w] { worker_loop(w); });
}

VecEnv::~VecEnv() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (auto& t : workers_) t.join();
}

void VecEnv::worker_loop(int worker) {
  std::uint64_t seen = 0;
  for (;;) {
    const std::function<void(std::size_t)>* work = nullptr;
    {
      std::unique_lock lock(mutex_);
      start_cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      work = work_;
    }
    for (std::size_t i = static_cast<std::size_t>(worker); i < envs_.size(); i += static_cast<std::size_t>(num_threads_))
      (*work)(i);
    std::lock_guard lock(mutex_);
    if (--pending_ == 0) done_cv_.notify_one();
  }
}

void VecEnv::run_parallel(const std::function<void(std::size_t)>& work) {
  if (num_threads_ > 1) {
    std::lock_guard lock(mutex_);
    work_ = &work;
    pending_ = num_threads_ - 1;
    ++generation_;
  }
  start_cv_.notify_all();
  for (std::size_t i = 0; i < envs_.size(); i += static_cast<std::size_t>(num_threads_)) work(i);
  if (num_threads_ > 1) {
    std::unique_lock lock(mutex_);
    done_cv_.wait(lock, [&] { return pending_ == 0; });
  }
}

void VecEnv::step(const std::vector<double>& actions) {
  const std::size_t na = action_space_.size();
  if (actions.size() != envs_.size() * na)
    throw base::UserError("learn: VecEnv.step: " + std::to_string(actions.size()) + " action values, expected " +
                          std::to_string(envs_.size()) + " copies × " + std::to_string(na));
  const std::function<void(std::size_t)> work = [&](std::size_t i) {
    StepResult& r = results_[i];
    envs_[i]->step(std::span<const double>(actions.data() + i * na, na), r);
    running_returns_[i] += r.reward;
    if (r.terminated || r.truncated) {
      envs_[i]->reset(observations_[i]);
      fresh_start_[i] = 1;
    } else {
      observations_[i] = r.observation;
    }
  };
  run_parallel(work);
  for (std::size_t i = 0; i < envs_.size(); ++i) {
    if (results_[i].terminated || results_[i].truncated) {
      finished_returns_.push_back(running_returns_[i]);
      running_returns_[i] = 0.0;
    }
  }
}

std::span<const Transition> VecEnv::take_start_transitions(std::size_t i) {
  if (!fresh_start_.at(i)) return {};
  fresh_start_[i] = 0;
  return envs_[i]->start_transitions();
}

std::vector<double> VecEnv::take_finished_returns() {
  std::vector<double> out;
  out.swap(finished_returns_);
  return out;
}

base::Json VecEnv::save_state() const {
  base::Json envs = base::Json::array();
  for (const auto& e : envs_) {
    const auto s = e->save_state();
    envs.push_back(s ? *s : base::Json());
  }
  return {{"envs", envs},
          {"observations", observations_},
          {"running_returns", running_returns_},
          {"finished_returns", finished_returns_}};
}

void VecEnv::load_state(const base::Json& state) {
  const auto& envs = state.at("envs");
  if (envs.size() != envs_.size())
    throw base::UserError("learn: VecEnv.load_state: checkpoint has " + std::to_string(envs.size()) +
                          " environments, this runner has " + std::to_string(envs_.size()));
  bool all_saved = true;
  for (const auto& e : envs) all_saved = all_saved && !e.is_null();
  if (!all_saved) return;  // environments without state support: keep the fresh episodes
  for (std::size_t i = 0; i < envs_.size(); ++i) envs_[i]->load_state(envs[i]);
  fresh_start_.assign(envs_.size(), 0);
  observations_ = state.at("observations").get<std::vector<std::vector<double>>>();
  running_returns_ = state.at("running_returns").get<std::vector<double>>();
  finished_returns_ = state.at("finished_returns").get<std::vector<double>>();
}

}  // namespace podium::learn
