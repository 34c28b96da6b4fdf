#include "nets.h"

#include <ATen/ops/_foreach_add.h>
#include <ATen/ops/_foreach_mul.h>
#include <malloc.h>
#include <torch/csrc/jit/api/module.h>
#include <torch/optim/adam.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>

#include "podium/base/error.h"

namespace podium::learn::detail {

Activation parse_activation(const std::string& name, const std::string& where) {
  if (name == "tanh") return Activation::tanh;
  if (name == "relu") return Activation::relu;
  throw base::UserError(where + ": activation \"" + name + "\" is not one of tanh, relu");
}

const char* activation_name(Activation a) { return a == Activation::tanh ? "tanh" : "relu"; }

MlpImpl::MlpImpl(int in, const std::vector<int>& hidden, int out, Activation act) : activation(act) {
  int width = in;
  std::vector<int> sizes = hidden;
  sizes.push_back(out);
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    layers.push_back(register_module("l" + std::to_string(i), torch::nn::Linear(width, sizes[i])));
    width = sizes[i];
  }
}

torch::Tensor MlpImpl::forward(torch::Tensor x) {
  for (std::size_t i = 0; i < layers.size(); ++i) {
    x = layers[i]->forward(x);
    if (i + 1 < layers.size()) x = activation == Activation::tanh ? torch::tanh(x) : torch::relu(x);
  }
  return x;
}

namespace {
void fill_uniform(const torch::Tensor& t, base::Rng& rng, double bound) {
  auto flat = t.data_ptr<float>();
  for (std::int64_t i = 0; i < t.numel(); ++i) flat[i] = static_cast<float>(rng.uniform(-bound, bound));
}
}  // namespace

void init_mlp(Mlp& net, base::Rng& rng, double output_scale) {
  torch::NoGradGuard no_grad;
  for (std::size_t i = 0; i < net->layers.size(); ++i) {
    auto& layer = net->layers[i];
    const double bound = 1.0 / std::sqrt(static_cast<double>(layer->weight.size(1)));
    const double scale = i + 1 == net->layers.size() ? output_scale : 1.0;
    fill_uniform(layer->weight, rng, bound * scale);
    fill_uniform(layer->bias, rng, bound * scale);
  }
}

torch::Tensor normal_tensor(base::Rng& rng, const std::vector<std::int64_t>& sizes) {
  auto t = torch::empty(sizes, torch::kFloat32);
  auto p = t.data_ptr<float>();
  for (std::int64_t i = 0; i < t.numel(); ++i) p[i] = static_cast<float>(rng.normal());
  return t;
}

torch::Tensor normalized_batch(const RunningNormalizer& normalizer, const std::vector<double>& rows_data, std::size_t rows) {
  const std::size_t n = normalizer.size();
  auto t = torch::empty({static_cast<std::int64_t>(rows), static_cast<std::int64_t>(n)}, torch::kFloat32);
  auto p = t.data_ptr<float>();
  for (std::size_t r = 0; r < rows; ++r)
    normalizer.normalize(std::span<const double>(rows_data.data() + r * n, n), std::span<float>(p + r * n, n));
  return t;
}

void soft_update(torch::nn::Module& target, const torch::nn::Module& source, double tau) {
  torch::NoGradGuard no_grad;
  // The per-tensor mul_/add_ as one call each: the same arithmetic, less dispatch.
  auto t = target.parameters();
  const auto s = source.parameters();
  at::_foreach_mul_(t, 1.0 - tau);
  at::_foreach_add_(t, s, tau);
}

void keep_freed_memory() {
  static std::once_flag once;
  // glibc returns freed blocks above its thresholds to the system, and each update's autograd
  // tensors then fault ~800 fresh pages back in (5-10% of a 256-256 SAC update).
  std::call_once(once, [] {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
  });
}

void hard_update(torch::nn::Module& target, const torch::nn::Module& source) {
  torch::NoGradGuard no_grad;
  auto t = target.parameters();
  auto s = source.parameters();
  for (std::size_t i = 0; i < t.size(); ++i) t[i].copy_(s[i]);
}

void set_adam_lr(torch::optim::Optimizer& optimizer, double lr) {
  for (auto& group : optimizer.param_groups()) static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
}

void append_parameters(const torch::nn::Module& module, std::vector<float>& out) {
  for (const auto& p : module.parameters()) {
    auto c = p.detach().contiguous();
    out.insert(out.end(), c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
  }
}

void write_json(torch::serialize::OutputArchive& archive, const std::string& key, const base::Json& value) {
  archive.write(key, c10::IValue(value.dump()));
}

base::Json read_json(torch::serialize::InputArchive& archive, const std::string& key) {
  c10::IValue v;
  archive.read(key, v);
  return base::Json::parse(v.toStringRef());
}

void deterministic_action(Mlp net, const RunningNormalizer* normalizer, const PolicyHead& head,
                          std::span<const double> observation, std::span<double> action, double scale) {
  PODIUM_CHECK(action.size() == std::size_t(head.action_size), "deterministic_action: action size");
  torch::NoGradGuard no_grad;
  const std::vector<double> raw(observation.begin(), observation.end());
  auto x = normalizer ? normalized_batch(*normalizer, raw, 1)
                      : torch::tensor(raw, torch::kFloat64).to(torch::kFloat32).reshape({1, std::int64_t(raw.size())});
  auto mu = net->forward(x).slice(1, 0, head.action_size);
  if (head.tanh_squash) mu = torch::tanh(mu);
  auto p = mu.accessor<float, 2>();
  const double bound = head.bound * scale;
  for (std::size_t j = 0; j < action.size(); ++j) {
    const double u = p[0][std::int64_t(j)];
    const double center = 0.5 * (head.high[j] + head.low[j]), half = 0.5 * (head.high[j] - head.low[j]);
    action[j] = center + half * (head.tanh_squash ? u * bound : std::clamp(u, -1.0, 1.0) * scale);
  }
}

void export_policy(const std::filesystem::path& path, const Mlp& net, const RunningNormalizer* normalizer,
                   std::size_t observation_size, const PolicyHead& head, const base::Json& record) {
  torch::jit::Module m("PodiumPolicy");
  m.register_attribute("podium_policy", c10::StringType::get(), c10::IValue(record.dump()));
  const auto f64 = torch::TensorOptions().dtype(torch::kFloat64);
  auto vec = [&](const std::vector<double>& v) { return torch::tensor(v, f64).clone(); };
  const std::vector<double> mean = normalizer ? normalizer->mean() : std::vector<double>(observation_size, 0.0);
  const std::vector<double> scale = normalizer ? normalizer->scale() : std::vector<double>(observation_size, 1.0);
  // Without a normaliser the clamp must not bite.
  const double clip = normalizer ? normalizer->clip() : 1e300;
  m.register_buffer("obs_mean", vec(mean));
  m.register_buffer("obs_scale", vec(scale));
  m.register_buffer("obs_clip", torch::tensor(clip, f64));
  std::vector<double> center(head.low.size()), half(head.low.size());
  for (std::size_t j = 0; j < center.size(); ++j) {
    center[j] = 0.5 * (head.high[j] + head.low[j]);
    half[j] = 0.5 * (head.high[j] - head.low[j]);
  }
  m.register_buffer("act_center", vec(center));
  m.register_buffer("act_half", vec(half));
  m.register_buffer("bound", torch::tensor(head.bound, f64));
  std::ostringstream src;
  // The same operations, in the same precision, as the C++ act() path (normalise in float64,
  // network in float32, head in float64), so both give the same actions.
  // Dtypes are written as c10::ScalarType numbers: without Python, `torch.float64` is unknown.
  const int f64_code = static_cast<int>(torch::kFloat64), f32_code = static_cast<int>(torch::kFloat32);
  src << "def forward(self, obs: Tensor) -> Tensor:\n"
      << "    x = torch.clamp((obs.to(" << f64_code << ") - self.obs_mean) / self.obs_scale, -self.obs_clip, "
      << "self.obs_clip).to(" << f32_code << ")\n";
  for (std::size_t i = 0; i < net->layers.size(); ++i) {
    m.register_buffer("w" + std::to_string(i), net->layers[i]->weight.detach().clone());
    m.register_buffer("b" + std::to_string(i), net->layers[i]->bias.detach().clone());
    src << "    x = torch.addmm(self.b" << i << ", x, self.w" << i << ".t())\n";
    if (i + 1 < net->layers.size()) src << "    x = torch." << activation_name(net->activation) << "(x)\n";
  }
  src << "    mu = x[:, 0:" << head.action_size << "]\n";
  if (head.tanh_squash) src << "    a = torch.tanh(mu).to(" << f64_code << ") * self.bound\n";
  else src << "    a = torch.clamp(mu.to(" << f64_code << "), -1.0, 1.0)\n";
  src << "    return self.act_center + self.act_half * a\n";
  m.define(src.str());
  m.save(path.string());
}

}  // namespace podium::learn::detail
