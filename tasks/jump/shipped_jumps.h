#pragma once
/// Jump policies evaluated without training (the demo's shipped quick-run strategies): each from
/// its own take-off state, at a bar height, with the P-VAE it was trained through.
#include <filesystem>
#include <string>
#include <vector>

#include "jump_evaluation.h"
#include "podium/base/config.h"

namespace podium::tasks::jump {

struct ShippedJump {
  std::string policy;           ///< TorchScript export of a jump trial
  std::string pose_vae;         ///< the P-VAE it acts through ("" : plain targets)
  std::vector<double> takeoff;  ///< its take-off features, in takeoff_features(kind)'s order
  double z_m = 0.0;             ///< the bar (box width) to jump
};

/// The `shipped` config list (paths relative to the spec file's folder); an entry's `z_m` 0 (or
/// absent) becomes `kind`'s starting z.
std::vector<ShippedJump> read_shipped_jumps(base::ConfigReader& r, JumpKind kind);

/// `jump` evaluation jumps (the first deterministic, recorded in `record_dir`) of `shipped` with
/// `settings` (its kind, model and rates). Throws base::UserError naming a missing file or a
/// take-off of the wrong size.
JumpEvaluation evaluate_shipped(const ShippedJump& shipped, JumpSettings settings, const EvaluationJumps& jumps,
                                const std::filesystem::path& record_dir);

}  // namespace podium::tasks::jump
