#pragma once
/// Episode starts for CharacterEnv.
#include <memory>
#include <utility>
#include <vector>

#include "podium/character/character_env.h"
#include "podium/sim/starts.h"

namespace podium::character {

/// Where on the ground a start puts the character, and which way it faces.
struct Placement {
  double x_m = 0.0, y_m = 0.0;
  double yaw_rad = 0.0;
};

/// The model's standing pose at rest, placed.
class StandingStart : public Start {
 public:
  explicit StandingStart(Placement at = {}) : at_(at) {}
  void begin(CharacterEnv& env, base::Rng& rng) const override;

 private:
  Placement at_;
};

/// The get-up seed's ragdoll fall: sim::ragdoll_start (§7: release from 1.5 m in a random pose,
/// torques a ~ N(0, σ)·limits for 80 control steps), with the torso turned before the release so
/// that the character lands on its back (supine) or front (prone) when asked, at a placement
/// (yaw uniform when `random_yaw`); `lying`, `at` and `random_yaw` replace those of `options`.
/// In an env that records start transitions (with TorqueActions), each of the fall's control steps
/// is one, under the action that maps to its torques (zero for the seed repository's fall).
class RagdollDrop : public Start {
 public:
  using Lying = sim::RagdollStart::Lying;
  RagdollDrop(sim::RagdollStart options, Lying lying, Placement at = {}, bool random_yaw = true)
      : options_(options), lying_(lying), at_(at), random_yaw_(random_yaw) {}
  void begin(CharacterEnv& env, base::Rng& rng) const override;

 private:
  sim::RagdollStart options_;
  Lying lying_;
  Placement at_;
  bool random_yaw_;
};

/// A frame of the env's reference clip with joint noise (reference-state initialisation; get-up
/// seed §6's ε-RSI uses it with probability ε): at a uniform time in [0, duration] or a fixed one,
/// velocities from the clip, each hinge angle + N(0, σ), each ball joint turned by a rotation
/// vector with N(0, σ) entries; raised when a geom would start below the ground. Sets the env's
/// reference clock to the frame's time.
class ReferenceStart : public Start {
 public:
  ReferenceStart(double joint_noise_rad, bool random_time, double time_s = 0.0)
      : noise_(joint_noise_rad), random_time_(random_time), time_s_(time_s) {}
  void begin(CharacterEnv& env, base::Rng& rng) const override;

 private:
  double noise_;
  bool random_time_;
  double time_s_;
};

/// A full state (q: nq, q̇: nv) and reference time (take-off states of the jumps; hand-over states).
class StateStart : public Start {
 public:
  StateStart(Eigen::VectorXd q, Eigen::VectorXd qd, double reference_time_s = 0.0)
      : q_(std::move(q)), qd_(std::move(qd)), reference_time_s_(reference_time_s) {}
  void begin(CharacterEnv& env, base::Rng& rng) const override;

 private:
  Eigen::VectorXd q_, qd_;
  double reference_time_s_;
};

/// One of several starts, chosen with the given weights each episode (e.g. ε-RSI: a
/// ReferenceStart with weight ε, a RagdollDrop with 1 − ε).
class ChoiceStart : public Start {
 public:
  explicit ChoiceStart(std::vector<std::pair<double, std::unique_ptr<Start>>> options);
  void begin(CharacterEnv& env, base::Rng& rng) const override;

 private:
  std::vector<std::pair<double, std::unique_ptr<Start>>> options_;
  double total_ = 0.0;
};

}  // namespace podium::character
