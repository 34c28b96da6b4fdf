#include "podium/learn/normalizer.h"

#include <algorithm>
#include <cmath>

#include "podium/base/error.h"

namespace podium::learn {

RunningNormalizer::RunningNormalizer(std::size_t size, double clip, double epsilon)
    : mean_(size, 0.0), var_(size, 1.0), clip_(clip), epsilon_(epsilon) {}

void RunningNormalizer::update(std::span<const double> data, std::size_t rows) {
  const std::size_t n = size();
  PODIUM_CHECK(data.size() == rows * n, "normaliser update: data is rows × size");
  if (rows == 0) return;
  std::vector<double> batch_mean(n, 0.0), batch_var(n, 0.0);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t j = 0; j < n; ++j) batch_mean[j] += data[r * n + j];
  for (double& m : batch_mean) m /= static_cast<double>(rows);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t j = 0; j < n; ++j) {
      const double d = data[r * n + j] - batch_mean[j];
      batch_var[j] += d * d;
    }
  for (double& v : batch_var) v /= static_cast<double>(rows);
  // Chan, Golub & LeVeque (1979): merge (count, mean, M2) of two samples.
  const double nb = static_cast<double>(rows), total = count_ + nb;
  for (std::size_t j = 0; j < n; ++j) {
    const double delta = batch_mean[j] - mean_[j];
    const double m2 = var_[j] * count_ + batch_var[j] * nb + delta * delta * count_ * nb / total;
    mean_[j] += delta * nb / total;
    var_[j] = m2 / total;
  }
  count_ = total;
}

void RunningNormalizer::normalize(std::span<const double> x, std::span<float> out) const {
  PODIUM_CHECK(x.size() == size() && out.size() == size(), "normaliser input and output have size()");
  for (std::size_t j = 0; j < size(); ++j)
    out[j] = static_cast<float>(std::clamp((x[j] - mean_[j]) / std::sqrt(var_[j] + epsilon_), -clip_, clip_));
}

std::vector<double> RunningNormalizer::scale() const {
  std::vector<double> s(size());
  for (std::size_t j = 0; j < size(); ++j) s[j] = std::sqrt(var_[j] + epsilon_);
  return s;
}

base::Json RunningNormalizer::save() const {
  return {{"mean", mean_}, {"variance", var_}, {"count", count_}, {"clip", clip_}, {"epsilon", epsilon_}};
}

void RunningNormalizer::load(const base::Json& state) {
  auto mean = state.at("mean").get<std::vector<double>>();
  if (mean.size() != size())
    throw base::UserError("learn: normaliser state has " + std::to_string(mean.size()) + " entries, expected " +
                          std::to_string(size()));
  mean_ = std::move(mean);
  var_ = state.at("variance").get<std::vector<double>>();
  count_ = state.at("count").get<double>();
  clip_ = state.at("clip").get<double>();
  epsilon_ = state.at("epsilon").get<double>();
}

}  // namespace podium::learn
