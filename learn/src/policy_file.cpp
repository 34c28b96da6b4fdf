#include "policy_file.h"

#include <torch/types.h>

#include "podium/base/error.h"

namespace podium::learn::detail {

base::Json policy_record(const std::string& algorithm, const Mlp& net, std::size_t observation_size, const BoxSpace& action_space,
                         double bound, const RunningNormalizer* normalizer) {
  std::vector<int> hidden;
  for (std::size_t i = 0; i + 1 < net->layers.size(); ++i) hidden.push_back(int(net->layers[i]->weight.size(0)));
  return {{"algorithm", algorithm},
          {"hidden", hidden},
          {"activation", activation_name(net->activation)},
          {"observation_size", observation_size},
          {"action_low", action_space.low},
          {"action_high", action_space.high},
          {"bound", bound},
          {"normalizer", normalizer ? normalizer->save() : base::Json()}};
}

PolicyFile read_policy_file(const std::filesystem::path& path) {
  const std::string where = "learn: policy file " + path.string();
  if (!std::filesystem::is_regular_file(path)) throw base::UserError(where + " does not exist");
  PolicyFile file;
  try {
    file.archive.load_from(path.string());
  } catch (const c10::Error&) {
    throw base::UserError(where + " is not a torch archive (expected a learner checkpoint or TorchScript export)");
  }
  c10::IValue value;
  if (file.archive.try_read("podium_policy", value)) {
    file.record = base::Json::parse(value.toStringRef());
  } else if (file.archive.try_read("state", value)) {
    const base::Json state = base::Json::parse(value.toStringRef());
    if (!state.contains("policy")) throw base::UserError(where + " is a checkpoint without a policy record");
    file.record = state.at("policy");
    file.checkpoint = true;
  } else {
    throw base::UserError(where + " is neither a learner checkpoint nor a TorchScript policy export");
  }
  const base::Json& r = file.record;
  const std::string algorithm = r.at("algorithm").get<std::string>();
  const bool sac = algorithm == "sac";
  file.head.action_size = int(r.at("action_low").size());
  file.head.tanh_squash = sac;
  file.head.bound = r.at("bound").get<double>();
  file.head.low = r.at("action_low").get<std::vector<double>>();
  file.head.high = r.at("action_high").get<std::vector<double>>();
  const int n_obs = r.at("observation_size").get<int>();
  file.net = Mlp(n_obs, r.at("hidden").get<std::vector<int>>(), (sac ? 2 : 1) * file.head.action_size,
                 parse_activation(r.at("activation").get<std::string>(), where));
  if (!r.at("normalizer").is_null()) {
    file.normalizer.emplace(std::size_t(n_obs));
    file.normalizer->load(r.at("normalizer"));
  }
  if (file.checkpoint) {
    torch::serialize::InputArchive net;
    file.archive.read(sac ? "actor" : "policy", net);
    file.net->load(net);
  } else {
    torch::NoGradGuard no_grad;
    for (std::size_t i = 0; i < file.net->layers.size(); ++i) {
      torch::Tensor w, b;
      file.archive.read("w" + std::to_string(i), w, /*is_buffer=*/true);
      file.archive.read("b" + std::to_string(i), b, /*is_buffer=*/true);
      file.net->layers[i]->weight.copy_(w);
      file.net->layers[i]->bias.copy_(b);
    }
  }
  return file;
}

void check_warm_start(const PolicyFile& source, const base::Json& mine, const std::filesystem::path& path) {
  const std::string where = mine.at("algorithm").get<std::string>() + ": warm start from " + path.string() + ": ";
  for (const char* key : {"algorithm", "hidden", "activation", "observation_size", "action_low", "action_high"})
    if (source.record.at(key) != mine.at(key))
      throw base::UserError(where + key + " is " + source.record.at(key).dump() + " there but " + mine.at(key).dump() + " here");
  if (source.record.at("normalizer").is_null() != mine.at("normalizer").is_null())
    throw base::UserError(where + "normalize_observations differs (" + (source.normalizer ? "on" : "off") + " there)");
}

}  // namespace podium::learn::detail
