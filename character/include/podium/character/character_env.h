#pragma once
/// CharacterEnv: a learn::Env over one sim::World, assembled from parts — an action map, a list
/// of observation parts, a start — plus the task's reward. Tasks (tasks/*) choose and configure
/// parts; the parts themselves live in actions.h, observations.h and starts.h.
///
/// An episode: before_episode (e.g. a per-episode strength, get-up seed §5) → start → at most
/// episode_steps control steps, each: action → world command → one control step → reward →
/// observation. A non-finite physics state ends the episode as terminated with reward 0.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "podium/base/rng.h"
#include "podium/character/motion.h"
#include "podium/learn/env.h"
#include "podium/sim/world.h"

namespace podium::character {

class CharacterEnv;

/// Turns a policy action into the World's command.
class ActionMap {
 public:
  virtual ~ActionMap() = default;
  virtual learn::BoxSpace space(const sim::CharacterModel& model) const = 0;
  virtual sim::Control control() const = 0;
  /// Writes the command for `action` (sized as sim::World::control_step wants for control()).
  virtual void command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const = 0;
};

/// One block of the observation vector.
class ObservationPart {
 public:
  virtual ~ObservationPart() = default;
  virtual std::size_t size(const sim::CharacterModel& model) const = 0;
  /// Writes size() values for the env's current state.
  virtual void write(const CharacterEnv& env, std::span<double> out) const = 0;
};

/// Puts the World in an episode's first state (World::reset or steps of its own, e.g. a fall).
class Start {
 public:
  virtual ~Start() = default;
  virtual void begin(CharacterEnv& env, base::Rng& rng) const = 0;
};

/// The task's reward and termination for one control step: sets out.reward, out.terminated and
/// out.info (sized as info_names), and out.truncated when an episode of its own length ends (a
/// reference-driven one, say); CharacterEnv also truncates at episode_steps and sets the observation.
/// The env is passed mutable, so a task's CharacterEnv subclass may update its episode's trackers
/// here (a lambda taking `const CharacterEnv&` binds as well).
using RewardFn = std::function<void(CharacterEnv& env, std::span<const double> action, learn::StepResult& out)>;
/// Per-episode changes before the start (strength β̂, friction, the reference clip's κ, ...).
using EpisodeHook = std::function<void(CharacterEnv& env, base::Rng& rng)>;

struct CharacterEnvParts {
  sim::ModelPtr model;
  sim::WorldConfig world;
  int episode_steps = 250;  ///< control steps before truncation (get-up seed §4: 250)
  std::unique_ptr<ActionMap> action;
  std::vector<std::unique_ptr<ObservationPart>> observation;
  std::unique_ptr<Start> start;
  RewardFn reward;
  std::vector<std::string> info_names;
  EpisodeHook before_episode;
  /// The reference motion, for residual actions, reference observations and clip starts; its
  /// clock advances one control period per step from the time the start sets.
  std::shared_ptr<const Clip> reference;
  /// Keep the start's control steps as learn::Transitions (start_transitions()) for an
  /// off-policy learner to store, rewarded by `reward` (get-up seed repository: the fall's).
  bool record_start_transitions = false;
};

class CharacterEnv : public learn::Env {
 public:
  /// Throws base::UserError when a required part is missing.
  explicit CharacterEnv(CharacterEnvParts parts);

  learn::BoxSpace observation_space() const override;
  learn::BoxSpace action_space() const override { return action_space_; }
  std::vector<std::string> info_names() const override { return parts_.info_names; }
  void seed(std::uint64_t seed) override { rng_ = base::Rng(seed); }
  void reset(std::vector<double>& observation) override;
  void step(std::span<const double> action, learn::StepResult& out) override;
  /// The World's snapshot (sim::WorldSnapshot::to_json: state, contact warm starts, friction,
  /// strength, terrain, forces; exact), episode clock, reference clock, last action and
  /// generator. Loaded into an env built from the same parts (in this process or another), the
  /// episode continues bitwise as the saved one would have.
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

  /// Recomputes the features and writes the observation of the current World state (for tests
  /// and for tasks that edit the state mid-episode).
  void observe(std::vector<double>& observation);

  /// The start's transitions of this episode (with CharacterEnvParts::record_start_transitions).
  std::span<const learn::Transition> start_transitions() const override { return start_transitions_; }
  bool records_start_transitions() const { return parts_.record_start_transitions; }
  /// For a Start that steps the World: the first call of an episode notes the state the start
  /// begins from; each later one adds the transition from the previously noted state to the
  /// current one under `action` (in action_space()), rewarded by the task's reward. Does nothing
  /// unless the env records start transitions.
  void note_start_state(std::span<const double> action);

  sim::World& world() { return *world_; }
  const sim::World& world() const { return *world_; }
  const sim::CharacterModel& model() const { return *parts_.model; }
  const ActionMap& action_map() const { return *parts_.action; }
  /// sim::World::observe() of the current state (refreshed after every reset and step).
  const sim::Observation& features() const { return features_; }
  /// Control steps taken in this episode.
  int step_index() const { return step_; }
  int episode_steps() const { return parts_.episode_steps; }
  double control_dt_s() const { return 1.0 / parts_.world.control_hz; }
  const Clip* reference() const { return parts_.reference.get(); }
  void set_reference(std::shared_ptr<const Clip> clip) { parts_.reference = std::move(clip); }
  double reference_time_s() const { return reference_time_s_; }
  void set_reference_time(double t_s) { reference_time_s_ = t_s; }
  /// The action of the last step (empty before the first).
  const std::vector<double>& last_action() const { return last_action_; }
  base::Rng& rng() { return rng_; }

 private:
  CharacterEnvParts parts_;
  std::unique_ptr<sim::World> world_;
  learn::BoxSpace action_space_;
  std::size_t observation_size_ = 0;
  sim::Observation features_;
  Eigen::VectorXd command_;
  std::vector<double> last_action_;
  base::Rng rng_;
  int step_ = 0;
  double reference_time_s_ = 0.0;
  std::vector<learn::Transition> start_transitions_;
  std::vector<double> start_state_;  // the last noted start state's observation
  bool start_noted_ = false;
};

}  // namespace podium::character
