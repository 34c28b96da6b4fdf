#include "shipped_jumps.h"

#include "jump_schedules.h"
#include "podium/learn/frozen_policy.h"
#include "pose_prior.h"

namespace podium::tasks::jump {

std::vector<ShippedJump> read_shipped_jumps(base::ConfigReader& r, JumpKind kind) {
  return r.objects(
      "shipped",
      [kind](base::ConfigReader& p) {
        ShippedJump s;
        s.policy = p.file("policy", base::required, "a jump trial's TorchScript policy");
        s.pose_vae = p.file("pose_vae", "", "the P-VAE it was trained through (\"\": plain targets)");
        s.takeoff = p.numbers("takeoff", {}, {}, "its take-off features, in the order of the explore stage's params");
        s.z_m = p.number("z_m", 0.0, {.min = 0.0, .max = 3.0}, "the bar height (box width) to jump; 0: the kind's starting z");
        if (s.z_m == 0.0) s.z_m = difficulty_curriculum(kind).initial;
        return s;
      },
      "evaluate: trial i jumps entry i mod n (paths relative to the spec file's folder)");
}

JumpEvaluation evaluate_shipped(const ShippedJump& shipped, JumpSettings settings, const EvaluationJumps& jumps,
                                const std::filesystem::path& record_dir) {
  settings.takeoff_features = shipped.takeoff;
  settings.difficulty_m = shipped.z_m;
  PosePrior prior;
  if (!shipped.pose_vae.empty()) prior = load_pose_prior(shipped.pose_vae);
  JumpEnv env(settings, prior);
  const learn::FrozenPolicy policy(shipped.policy);
  return evaluate_jumps(
      env, [&](std::span<const double> o, std::span<double> a) { policy.act(o, a, 1.0); }, jumps, record_dir);
}

}  // namespace podium::tasks::jump
