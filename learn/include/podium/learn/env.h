#pragma once
/// The environment contract tasks implement for learn/'s trainers (docs/architecture.md "Physics and learning").
///
/// Gymnasium semantics: an episode ends either by *termination* (a terminal state of the MDP,
/// e.g. a fall: no bootstrapping from the next state) or by *truncation* (a time limit: the
/// value of the next state is still bootstrapped). Actions are continuous boxes; trainers work in
/// the normalised box [-1, 1]^n and rescale to action_space() before calling step().
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::learn {

/// A box [low, high]^n; infinite bounds are allowed for observations.
struct BoxSpace {
  std::vector<double> low;
  std::vector<double> high;
  std::size_t size() const { return low.size(); }
};

/// What one step returns. The caller reuses one StepResult per environment (no allocation).
struct StepResult {
  std::vector<double> observation;  ///< next observation, observation_space().size()
  double reward = 0.0;
  bool terminated = false;   ///< terminal MDP state: do not bootstrap
  bool truncated = false;    ///< time limit or external cut: bootstrap from `observation`
  std::vector<double> info;  ///< extra per-step numbers, named by info_names()
};

/// A transition an environment took by itself while starting an episode, before reset() returned
/// the first observation (get-up seed: the fall's control steps, which the seed repository's
/// env.py reset adds to the replay buffer with their zero actions). `action` is in action_space().
struct Transition {
  std::vector<double> observation;
  std::vector<double> action;
  double reward = 0.0;
  std::vector<double> next_observation;
  bool terminated = false;
};

class Env {
 public:
  virtual ~Env() = default;
  virtual BoxSpace observation_space() const = 0;
  virtual BoxSpace action_space() const = 0;
  /// Names of StepResult::info entries (empty by default).
  virtual std::vector<std::string> info_names() const { return {}; }
  /// Seeds the environment's own generator (no global RNG); call before the first reset().
  virtual void seed(std::uint64_t seed) = 0;
  /// Starts an episode; writes the first observation.
  virtual void reset(std::vector<double>& observation) = 0;
  /// Applies `action` (inside action_space()) for one control step.
  virtual void step(std::span<const double> action, StepResult& out) = 0;
  /// The transitions the last reset() took before its first observation (none by default). An
  /// off-policy learner stores them; they are not environment steps (no step budget counts them).
  virtual std::span<const Transition> start_transitions() const { return {}; }
  /// This copy's action bound s for the current episode, as a fraction of the normalised box:
  /// SAC acts β·s·tanh(u) for it (get-up seed §5 and Algorithm 1: a per-episode torque
  /// multiplier β̂ ~ N(β^i, ε), drawn at each reset, which the observation should also carry).
  /// β·s must stay in (0, 1], so clip β̂ here. Read after each reset and step; PPO requires 1.
  virtual double action_scale() const { return 1.0; }
  /// Mid-episode state (including the generator) for learner checkpoints. std::nullopt means
  /// "not supported": a resumed trainer then starts fresh episodes instead of continuing them.
  virtual std::optional<base::Json> save_state() const { return std::nullopt; }
  virtual void load_state(const base::Json& state);
};

}  // namespace podium::learn
