#pragma once
// Reading a policy back from a learner's save_checkpoint() file or its export_torchscript()
// file, for warm starts and FrozenPolicy. Both files carry the same "policy" record (algorithm,
// network shape, spaces, β, normaliser), written by policy_record().
#include <torch/serialize/input-archive.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "nets.h"
#include "podium/base/json.h"
#include "podium/learn/env.h"
#include "podium/learn/normalizer.h"

namespace podium::learn::detail {

/// The record both file kinds carry: {"algorithm", "hidden", "activation", "observation_size",
/// "action_low", "action_high", "bound", "normalizer": RunningNormalizer::save() or null}.
base::Json policy_record(const std::string& algorithm, const Mlp& net, std::size_t observation_size, const BoxSpace& action_space,
                         double bound, const RunningNormalizer* normalizer);

struct PolicyFile {
  base::Json record;                            // policy_record() of the learner that wrote it
  bool checkpoint = false;                      // a save_checkpoint() file, else an export
  Mlp net{nullptr};                             // PPO's policy or SAC's actor
  std::optional<RunningNormalizer> normalizer;  // when the learner normalised observations
  PolicyHead head;
  torch::serialize::InputArchive archive;  // the whole file, for value / Q networks
};

/// Reads either file kind; throws UserError naming the file when it is neither.
PolicyFile read_policy_file(const std::filesystem::path& path);

/// Throws UserError unless `source` can be copied into a learner whose policy_record() is
/// `mine`: same algorithm, hidden widths, activation, spaces and use of a normaliser.
void check_warm_start(const PolicyFile& source, const base::Json& mine, const std::filesystem::path& path);

}  // namespace podium::learn::detail
