#pragma once
// Torch-side helpers shared by PPO, SAC and the VAEs: the MLP, initialisation from a project
// Rng (torch's global generator is never used), archive helpers and the TorchScript builder.
#include <torch/nn/module.h>
#include <torch/nn/modules/linear.h>
#include <torch/optim/optimizer.h>
#include <torch/serialize/archive.h>

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/base/rng.h"
#include "podium/learn/normalizer.h"

namespace podium::learn::detail {

enum class Activation { tanh, relu };
Activation parse_activation(const std::string& name, const std::string& where);
const char* activation_name(Activation a);

/// Fully connected network: Linear → act → … → Linear (no activation on the output).
struct MlpImpl : torch::nn::Module {
  MlpImpl(int in, const std::vector<int>& hidden, int out, Activation activation);
  torch::Tensor forward(torch::Tensor x);
  std::vector<torch::nn::Linear> layers;
  Activation activation;
};
TORCH_MODULE(Mlp);

/// PyTorch's default Linear initialisation, U(±1/sqrt(fan_in)), drawn from `rng`; the output
/// layer is scaled by `output_scale` (small policy outputs start near the mean action).
void init_mlp(Mlp& net, base::Rng& rng, double output_scale = 1.0);
/// A float32 tensor of N(0, 1) samples drawn from `rng`.
torch::Tensor normal_tensor(base::Rng& rng, const std::vector<std::int64_t>& sizes);
/// Rows of observations normalised into a float32 tensor [rows, size].
torch::Tensor normalized_batch(const RunningNormalizer& normalizer, const std::vector<double>& rows_data, std::size_t rows);

/// Polyak averaging target ← (1 − τ)·target + τ·source.
void soft_update(torch::nn::Module& target, const torch::nn::Module& source, double tau);
/// Makes glibc keep freed memory for reuse instead of returning it to the system (process-wide,
/// once): per-update tensors then stop page-faulting. Results do not change.
void keep_freed_memory();
/// Copies `source`'s parameters into `target` (same architecture).
void hard_update(torch::nn::Module& target, const torch::nn::Module& source);
/// Sets the learning rate of every parameter group of an Adam optimiser.
void set_adam_lr(torch::optim::Optimizer& optimizer, double lr);
/// Appends all parameters of `module`, flattened, to `out`.
void append_parameters(const torch::nn::Module& module, std::vector<float>& out);

void write_json(torch::serialize::OutputArchive& archive, const std::string& key, const base::Json& value);
base::Json read_json(torch::serialize::InputArchive& archive, const std::string& key);

/// How the exported policy turns the network output into an action in the environment box.
struct PolicyHead {
  int action_size = 0;            // the first action_size outputs are the mean
  bool tanh_squash = false;       // SAC: β·tanh(mean); PPO: clip(mean, −1, 1)
  double bound = 1.0;             // β
  std::vector<double> low, high;  // the environment's action box
};
/// The deterministic action of `net` for one observation, as every act() computes it: normalise
/// (float64) → network (float32) → β·s·tanh(mean) or clip(mean, −1, 1) → the action box, with
/// β = head.bound and s = `scale`. Thread-safe for concurrent callers sharing `net`.
void deterministic_action(Mlp net, const RunningNormalizer* normalizer, const PolicyHead& head,
                          std::span<const double> observation, std::span<double> action, double scale);
/// Builds and saves a torch::jit::Module computing the deterministic policy; `record` (the
/// policy_record() of policy_file.h) is stored in it as the string attribute "podium_policy".
void export_policy(const std::filesystem::path& path, const Mlp& net, const RunningNormalizer* normalizer,
                   std::size_t observation_size, const PolicyHead& head, const base::Json& record);

}  // namespace podium::learn::detail
