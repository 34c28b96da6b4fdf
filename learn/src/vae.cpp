#include "podium/learn/vae.h"

#include <ATen/Parallel.h>
#include <torch/optim/adam.h>
#include <torch/serialize.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "config_json.h"
#include "nets.h"
#include "podium/base/error.h"
#include "podium/learn/learner.h"

namespace podium::learn {

using detail::Mlp;

VaeConfig VaeConfig::pose_vae() {
  VaeConfig c;
  c.beta = 1e-5 * c.batch_size;
  return c;
}

VaeConfig VaeConfig::conditional() {
  VaeConfig c;
  c.latent_size = 16;
  c.epochs = 100;
  return c;
}

#define PODIUM_VAE_FIELDS(X) \
  X(latent_size)             \
  X(hidden)                  \
  X(beta)                    \
  X(learning_rate)           \
  X(batch_size)              \
  X(epochs)

PODIUM_CONFIG_JSON(VaeConfig, PODIUM_VAE_FIELDS, "vae config")

struct PoseVae::Impl {
  VaeConfig config;
  std::vector<double> lower, upper;
  std::int64_t n_pose, n_latent, n_cond;
  torch::Tensor mid, half;            // joint-limit box, float32 [n_pose]
  torch::Tensor cond_mean, cond_std;  // condition standardisation, float32 [n_cond]
  base::Rng rng;
  Mlp encoder, decoder;
  std::unique_ptr<torch::optim::Adam> opt;

  Impl(const VaeConfig& c, std::vector<double> lo, std::vector<double> hi, std::size_t cond, std::uint64_t seed)
      : config(c),
        lower(std::move(lo)),
        upper(std::move(hi)),
        n_pose(std::int64_t(lower.size())),
        n_latent(c.latent_size),
        n_cond(std::int64_t(cond)),
        rng(seed),
        encoder(int(n_pose + n_cond), c.hidden, int(2 * n_latent), detail::Activation::tanh),
        decoder(int(n_latent + n_cond), c.hidden, int(n_pose), detail::Activation::tanh) {
    if (lower.size() != upper.size() || lower.empty())
      throw base::UserError("vae: lower and upper limits need the same, non-zero size (got " + std::to_string(lower.size()) +
                            " and " + std::to_string(upper.size()) + ")");
    for (std::size_t k = 0; k < lower.size(); ++k)
      if (!(lower[k] < upper[k]))
        throw base::UserError("vae: limits of DoF " + std::to_string(k) + " [" + std::to_string(lower[k]) + ", " +
                              std::to_string(upper[k]) + "] are not an interval");
    if (c.latent_size < 1 || c.batch_size < 1 || c.epochs < 0)
      throw base::UserError("vae config: latent_size and batch_size must be ≥ 1, epochs ≥ 0");
    at::set_num_threads(1);
    setup_blas();
    std::vector<float> m(lower.size()), h(lower.size());
    for (std::size_t k = 0; k < lower.size(); ++k) {
      m[k] = float(0.5 * (upper[k] + lower[k]));
      h[k] = float(0.5 * (upper[k] - lower[k]));
    }
    mid = torch::tensor(m);
    half = torch::tensor(h);
    cond_mean = torch::zeros({n_cond});
    cond_std = torch::ones({n_cond});
    detail::init_mlp(encoder, rng);
    detail::init_mlp(decoder, rng);
    auto params = encoder->parameters();
    for (auto& p : decoder->parameters()) params.push_back(p);
    opt = std::make_unique<torch::optim::Adam>(params, torch::optim::AdamOptions(c.learning_rate));
  }

  torch::Tensor pose_in(const torch::Tensor& x) const { return (x - mid) / half; }
  torch::Tensor cond_in(const torch::Tensor& c) const { return (c - cond_mean) / cond_std; }
  std::pair<torch::Tensor, torch::Tensor> encode(const torch::Tensor& x, const torch::Tensor& c) {
    auto in = n_cond > 0 ? torch::cat({pose_in(x), cond_in(c)}, 1) : pose_in(x);
    auto out = encoder->forward(in);
    return {out.slice(1, 0, n_latent), out.slice(1, n_latent, 2 * n_latent)};
  }
  torch::Tensor decode(const torch::Tensor& z, const torch::Tensor& c) {
    auto in = n_cond > 0 ? torch::cat({z, cond_in(c)}, 1) : z;
    return mid + half * torch::tanh(decoder->forward(in));  // inside the joint limits by construction
  }

  torch::Tensor rows(const std::vector<std::vector<double>>& data, std::int64_t width, const char* what) const {
    auto t = torch::empty({std::int64_t(data.size()), width});
    auto p = t.data_ptr<float>();
    for (std::size_t i = 0; i < data.size(); ++i) {
      if (std::int64_t(data[i].size()) != width)
        throw base::UserError(std::string("vae: ") + what + "[" + std::to_string(i) + "] has " + std::to_string(data[i].size()) +
                              " values, expected " + std::to_string(width));
      std::copy(data[i].begin(), data[i].end(), p + std::int64_t(i) * width);
    }
    return t;
  }
  torch::Tensor conditions(const PoseDataset& d) const {
    if (n_cond == 0) return torch::zeros({std::int64_t(d.size()), 0});
    if (d.conditions.size() != d.poses.size())
      throw base::UserError("vae: this C-VAE needs one condition per pose (" + std::to_string(d.conditions.size()) + " for " +
                            std::to_string(d.poses.size()) + ")");
    return rows(d.conditions, n_cond, "conditions");
  }
  torch::Tensor vec(std::span<const double> v, std::int64_t width, const char* what) const {
    if (std::int64_t(v.size()) != width)
      throw base::UserError(std::string("vae: ") + what + " has " + std::to_string(v.size()) + " values, expected " +
                            std::to_string(width));
    std::vector<float> f(v.begin(), v.end());
    return torch::tensor(f).reshape({1, width});
  }
};

PoseVae::PoseVae(const VaeConfig& config, std::vector<double> lower, std::vector<double> upper, std::size_t condition_size,
                 std::uint64_t seed)
    : impl_(std::make_unique<Impl>(config, std::move(lower), std::move(upper), condition_size, seed)) {}
PoseVae::~PoseVae() = default;

std::size_t PoseVae::pose_size() const { return std::size_t(impl_->n_pose); }
std::size_t PoseVae::latent_size() const { return std::size_t(impl_->n_latent); }
std::size_t PoseVae::condition_size() const { return std::size_t(impl_->n_cond); }
const std::vector<double>& PoseVae::lower() const { return impl_->lower; }
const std::vector<double>& PoseVae::upper() const { return impl_->upper; }

std::vector<double> PoseVae::train(const PoseDataset& data, const EpochCallback& after_epoch) {
  auto& m = *impl_;
  if (data.size() == 0) throw base::UserError("vae: the pose dataset is empty");
  auto x_all = m.rows(data.poses, m.n_pose, "poses");
  auto c_all = m.conditions(data);
  if (m.n_cond > 0) {
    m.cond_mean = c_all.mean(0);
    m.cond_std = c_all.std(0, /*unbiased=*/false).clamp_min(1e-6);
  }
  const std::int64_t N = x_all.size(0), B = m.config.batch_size;
  std::vector<std::int64_t> perm(static_cast<std::size_t>(N));
  std::vector<double> losses;
  for (int epoch = 0; epoch < m.config.epochs; ++epoch) {
    std::iota(perm.begin(), perm.end(), 0);
    for (std::int64_t i = N - 1; i > 0; --i) std::swap(perm[std::size_t(i)], perm[std::size_t(m.rng.integer(0, i))]);
    double total = 0.0;
    std::int64_t batches = 0;
    for (std::int64_t s = 0; s < N; s += B) {
      auto idx = torch::from_blob(perm.data() + s, {std::min(B, N - s)}, torch::kInt64);
      auto x = x_all.index_select(0, idx);
      auto c = c_all.index_select(0, idx);
      auto [mu, log_var] = m.encode(x, c);
      auto z = mu + torch::exp(0.5 * log_var) * detail::normal_tensor(m.rng, {x.size(0), m.n_latent});
      // thesis §3.4.2: MSE reconstruction + β·KL(N(μ, σ²) ‖ N(0, I)).
      auto recon = (m.decode(z, c) - x).pow(2).mean();
      auto kl = (-0.5 * (1 + log_var - mu.pow(2) - log_var.exp()).sum(1)).mean();
      auto loss = recon + m.config.beta * kl;
      m.opt->zero_grad();
      loss.backward();
      m.opt->step();
      total += loss.item<double>();
      ++batches;
    }
    losses.push_back(total / double(batches));
    if (after_epoch && !after_epoch(epoch, losses.back())) break;
  }
  return losses;
}

PoseVae::Posterior PoseVae::posterior(std::span<const double> pose, std::span<const double> condition) const {
  auto& m = *impl_;
  torch::NoGradGuard no_grad;
  auto [mu, log_var] = m.encode(m.vec(pose, m.n_pose, "pose"), m.vec(condition, m.n_cond, "condition"));
  // The same σ as the reparameterisation in train().
  auto mean = mu.contiguous(), std = torch::exp(0.5 * log_var).contiguous();
  return {{mean.data_ptr<float>(), mean.data_ptr<float>() + m.n_latent},
          {std.data_ptr<float>(), std.data_ptr<float>() + m.n_latent}};
}

std::vector<double> PoseVae::encode(std::span<const double> pose, std::span<const double> condition) const {
  return posterior(pose, condition).mean;
}

std::vector<double> PoseVae::decode(std::span<const double> latent, std::span<const double> condition) const {
  auto& m = *impl_;
  torch::NoGradGuard no_grad;
  auto x = m.decode(m.vec(latent, m.n_latent, "latent"), m.vec(condition, m.n_cond, "condition")).contiguous();
  std::vector<double> out(x.data_ptr<float>(), x.data_ptr<float>() + m.n_pose);
  // float32 round-off may step a hair outside a limit; the limits are the contract.
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = std::clamp(out[k], m.lower[k], m.upper[k]);
  return out;
}

double PoseVae::reconstruction_rmse(const PoseDataset& data) const {
  auto& m = *impl_;
  torch::NoGradGuard no_grad;
  auto x = m.rows(data.poses, m.n_pose, "poses");
  auto c = m.conditions(data);
  auto recon = m.decode(m.encode(x, c).first, c);
  return std::sqrt((recon - x).pow(2).mean().item<double>());
}

void PoseVae::save(const std::filesystem::path& path) const {
  const auto& m = *impl_;
  torch::serialize::OutputArchive archive, enc, dec, opt;
  m.encoder->save(enc);
  m.decoder->save(dec);
  m.opt->save(opt);
  archive.write("encoder", enc);
  archive.write("decoder", dec);
  archive.write("optimizer", opt);
  archive.write("cond_mean", m.cond_mean);
  archive.write("cond_std", m.cond_std);
  detail::write_json(archive, "state",
                     {{"config", m.config.to_json()}, {"lower", m.lower}, {"upper", m.upper}, {"rng", m.rng.save()}});
  archive.save_to(path.string());
}

void PoseVae::load(const std::filesystem::path& path) {
  auto& m = *impl_;
  torch::serialize::InputArchive archive, enc, dec, opt;
  archive.load_from(path.string());
  const base::Json state = detail::read_json(archive, "state");
  if (state.at("config") != m.config.to_json() || state.at("lower") != base::Json(m.lower) ||
      state.at("upper") != base::Json(m.upper))
    throw base::UserError("vae: " + path.string() + " was saved with another config or joint limits");
  archive.read("encoder", enc);
  archive.read("decoder", dec);
  archive.read("optimizer", opt);
  m.encoder->load(enc);
  m.decoder->load(dec);
  m.opt->load(opt);
  torch::Tensor mean, std;
  archive.read("cond_mean", mean);
  archive.read("cond_std", std);
  m.cond_mean = mean;
  m.cond_std = std;
  m.rng.load(state.at("rng").get<std::string>());
}

std::unique_ptr<PoseVae> PoseVae::from_file(const std::filesystem::path& path) {
  const std::string where = path.string();
  if (!std::filesystem::is_regular_file(path)) throw base::UserError("pose VAE: " + where + ": no such file");
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(where);
    const base::Json state = detail::read_json(archive, "state");
    torch::Tensor cond_mean;
    archive.read("cond_mean", cond_mean);
    auto vae = std::make_unique<PoseVae>(VaeConfig::from_json(state.at("config")), state.at("lower").get<std::vector<double>>(),
                                         state.at("upper").get<std::vector<double>>(), std::size_t(cond_mean.numel()), 0);
    vae->load(path);
    return vae;
  } catch (const c10::Error& e) {
    // torch's messages run over many lines (a backtrace); its first line says what was wrong.
    const std::string message = e.what_without_backtrace();
    throw base::UserError("pose VAE: " + where + ": not a saved VAE (" + message.substr(0, message.find('\n')) + ")");
  } catch (const base::Json::exception& e) {
    throw base::UserError("pose VAE: " + where + ": not a saved VAE (" + e.what() + ")");
  }
}

std::vector<double> pose_action_to_target(const PoseVae& vae, std::span<const double> action, std::span<const double> condition) {
  const std::size_t nz = vae.latent_size(), nq = vae.pose_size();
  if (action.size() != nz + nq)
    throw base::UserError("pose action has " + std::to_string(action.size()) + " values, expected latent " + std::to_string(nz) +
                          " + offsets " + std::to_string(nq));
  auto target = vae.decode(action.subspan(0, nz), condition);
  for (std::size_t k = 0; k < nq; ++k) target[k] = std::clamp(target[k] + action[nz + k], vae.lower()[k], vae.upper()[k]);
  return target;
}

}  // namespace podium::learn
