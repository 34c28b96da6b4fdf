#pragma once
/// The captured high-jump techniques as strategy features: the Fosbury flop, straddle and scissor
/// jumps of the authors' motion capture (arpspoof/Jump's data/motions/beyond, DeepMimic format;
/// never copied into the repository), each reduced to the Stage 1 feature of
/// strategy_feature.h at the frame where its centre of mass peaks (the captures have no bar), so a
/// discovered strategy is labelled by its nearest technique.
#include <filesystem>
#include <string>
#include <vector>

#include "podium/sim/model.h"

namespace podium::tasks::jump {

struct CapturedTechnique {
  std::string name;         ///< "Fosbury flop", "straddle", "scissor"
  std::string file;         ///< the capture's file name
  double up_angle_rad = 0;  ///< Stage 1's feature at the COM peak
  double peak_com_m = 0;    ///< the COM's height there
};

/// The three techniques read from `motions_dir` (the folder holding VC5_high_jump__*.txt) on
/// `model` (the athlete: the captures' skeleton, humanoid3d's joint names). Throws
/// base::UserError naming a missing or unreadable file.
std::vector<CapturedTechnique> captured_techniques(const std::filesystem::path& motions_dir, const sim::ModelPtr& model);

/// The technique nearest a Stage 1 feature (|Δ up-angle|); `techniques` must not be empty.
const CapturedTechnique& nearest_technique(const std::vector<CapturedTechnique>& techniques, double up_angle_rad);

}  // namespace podium::tasks::jump
