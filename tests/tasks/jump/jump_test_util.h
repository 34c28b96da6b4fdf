#pragma once
// Shared by the jump env tests: settings on the athlete and scripted states.
#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>

#include "jump_env.h"
#include "podium/character/frames.h"
#include "podium/character/pose_bridge.h"
#include "shared_data.h"

namespace podium::tasks::jump::testing {

inline JumpSettings settings(JumpKind kind = JumpKind::high_jump, double z_m = 0.5) {
  JumpSettings s;  // model: "athlete"
  s.kind = kind;
  s.difficulty_m = z_m;
  return s;
}

// The action that holds the current joint pose (plain targets: the action is the pose).
inline std::vector<double> hold_pose(const JumpEnv& env) {
  return character::PoseBridge(env.world().model_ptr()).pose(env.world().data().q);
}

// The standing pose turned by `rotation` about the root, root at `root` (world), at rest; puts it
// into the env's World (after a reset: the episode's trackers stay as the reset left them).
inline void place(JumpEnv& env, const Eigen::Vector3d& root,
                  const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity()) {
  Eigen::VectorXd q = env.model().standing_pose();
  q.head<3>() = root;
  character::set_quat(q, 3, rotation);
  env.world().set_state(q, Eigen::VectorXd::Zero(env.model().nv()));
}

// Steps holding the pose until the rules decide (at most `max_steps`); returns the last step.
inline learn::StepResult step_until_decided(JumpEnv& env, int max_steps = 100) {
  learn::StepResult out;
  for (int i = 0; i < max_steps; ++i) {
    env.step(hold_pose(env), out);
    if (out.terminated || out.truncated) break;
  }
  return out;
}

// ../shared/data/jump/data, or empty when PODIUM_SHARED_DIR is unset or the folder is absent.
inline std::filesystem::path captured_jump_dir() { return podium::testing::shared_data("jump/data"); }

}  // namespace podium::tasks::jump::testing
