#pragma once
/// Observation parts for CharacterEnv. "Heading frame": the root's facing direction on the
/// ground (frames.h); parts marked *facing-invariant* give the same values when the whole
/// character is turned about the vertical and moved horizontally (on flat ground).
#include <functional>
#include <string>
#include <vector>

#include "podium/character/character_env.h"
#include "podium/character/pose_bridge.h"

namespace podium::character {

/// Joint angles as the bridge's z-up pose (hinge angles, ball exponential maps): nv − 6 values.
/// Facing-invariant.
class JointAngles : public ObservationPart {
 public:
  explicit JointAngles(sim::ModelPtr model) : bridge_(std::move(model)) {}
  std::size_t size(const sim::CharacterModel& model) const override { return model.nv() - 6; }
  void write(const CharacterEnv& env, std::span<double> out) const override;

 private:
  PoseBridge bridge_;
};

/// Joint velocities (q̇ without the root): nv − 6 values. Facing-invariant.
class JointVelocities : public ObservationPart {
 public:
  std::size_t size(const sim::CharacterModel& model) const override { return model.nv() - 6; }
  void write(const CharacterEnv& env, std::span<double> out) const override;
};

/// The root's angular and linear velocity in its own frame (q̇'s first 6 entries): 6 values, what
/// dm_control's `velocity` adds to the joint velocities (the get-up seed repository's state). How
/// fast the body tips, which balance needs and no other part gives. Facing-invariant.
class RootVelocity : public ObservationPart {
 public:
  std::size_t size(const sim::CharacterModel&) const override { return 6; }
  void write(const CharacterEnv& env, std::span<double> out) const override;
};

/// Head height above the ground below it (get-up seed App. C): 1 value. Facing-invariant.
class HeadHeight : public ObservationPart {
 public:
  std::size_t size(const sim::CharacterModel&) const override { return 1; }
  void write(const CharacterEnv& env, std::span<double> out) const override;
};

/// Per body, in the heading frame: position relative to the root origin (3), rotation as its
/// first two matrix columns (6), linear and angular velocity (3 + 3), each block optional
/// (DeepMimic-style link state; thesis §3.6.2). Size: bodies × chosen blocks. Facing-invariant.
/// With Frame::world the same blocks are in world axes instead (thesis §3.4.1: the jumps' global
/// features, which tell states apart by where the character faces relative to the bar); not
/// facing-invariant.
class LinkStates : public ObservationPart {
 public:
  struct Blocks {
    bool positions = true, rotations = true, velocities = true;
  };
  enum class Frame { heading, world };
  explicit LinkStates(Blocks blocks, Frame frame = Frame::heading) : blocks_(blocks), frame_(frame) {}
  std::size_t size(const sim::CharacterModel& model) const override;
  void write(const CharacterEnv& env, std::span<double> out) const override;

 private:
  Blocks blocks_;
  Frame frame_;
};

/// End effectors relative to the root link in its own frame (get-up seed App. C, egocentric):
/// 3 per end-effector body of the model. Facing-invariant.
class EndEffectors : public ObservationPart {
 public:
  std::size_t size(const sim::CharacterModel& model) const override { return 3 * model.end_effector_bodies().size(); }
  void write(const CharacterEnv& env, std::span<double> out) const override;
};

/// Centre of mass: its height above the ground below it, then its velocity in the heading frame
/// (get-up seed App. C's COM velocity; sprint seed's COM terms): 4 values. Facing-invariant.
class CenterOfMass : public ObservationPart {
 public:
  std::size_t size(const sim::CharacterModel&) const override { return 4; }
  void write(const CharacterEnv& env, std::span<double> out) const override;
};

/// The torso's front (x), side (y) and up (z) axes. `vertical_only`: their z components
/// [x_up, y_up, z_up] (get-up seed App. C), 3 values; otherwise all three axes in the heading
/// frame, 9 values. Facing-invariant.
class TorsoAxes : public ObservationPart {
 public:
  explicit TorsoAxes(bool vertical_only) : vertical_only_(vertical_only) {}
  std::size_t size(const sim::CharacterModel&) const override { return vertical_only_ ? 3 : 9; }
  void write(const CharacterEnv& env, std::span<double> out) const override;

 private:
  bool vertical_only_;
};

/// The 5×5 height map (curve get-up seed §3.2: a 1 m × 1 m grid at 25 cm aligned with the
/// character): the root's height above the terrain at each grid point of the heading frame,
/// row-major from (−2, −2)·spacing. 25 values. Facing-invariant on flat ground.
class HeightMap : public ObservationPart {
 public:
  explicit HeightMap(double spacing_m = 0.25) : spacing_m_(spacing_m) {}
  std::size_t size(const sim::CharacterModel&) const override { return 25; }
  void write(const CharacterEnv& env, std::span<double> out) const override;

 private:
  double spacing_m_;
};

/// Reference frames ahead (get-up seed §6: frames t+1 and t+5 of the reference in the state):
/// per offset k (control steps), the reference pose at reference time + k·dt — its z-up joint
/// pose (nv − 6), its root position relative to the character's root in the heading frame (3)
/// and its root rotation in the heading frame (6). Facing-invariant only if the reference turns
/// with the character (it is fixed in the world).
class ReferenceFrames : public ObservationPart {
 public:
  ReferenceFrames(sim::ModelPtr model, std::vector<int> steps_ahead)
      : bridge_(std::move(model)), steps_(std::move(steps_ahead)) {}
  std::size_t size(const sim::CharacterModel& model) const override { return steps_.size() * (model.nv() - 6 + 9); }
  void write(const CharacterEnv& env, std::span<double> out) const override;

 private:
  PoseBridge bridge_;
  std::vector<int> steps_;
};

/// Task scalars (the strength β^i of s_weak, a phase, a target): `count` values from `fn`.
class TaskScalars : public ObservationPart {
 public:
  using Fn = std::function<void(const CharacterEnv& env, std::span<double> out)>;
  TaskScalars(std::size_t count, Fn fn) : count_(count), fn_(std::move(fn)) {}
  std::size_t size(const sim::CharacterModel&) const override { return count_; }
  void write(const CharacterEnv& env, std::span<double> out) const override { fn_(env, out); }

 private:
  std::size_t count_;
  Fn fn_;
};

/// World-frame angular and linear velocity of every link origin, from q and q̇ (O(n)); needs
/// forward kinematics of the same q in `data`.
void link_velocities(const sim::CharacterModel& model, const sim::CharacterData& data, std::vector<Eigen::Vector3d>& omega,
                     std::vector<Eigen::Vector3d>& velocity);

}  // namespace podium::character
