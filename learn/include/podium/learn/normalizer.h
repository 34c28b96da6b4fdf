#pragma once
/// Observation normalisation with running statistics: x̂ = clip((x − μ) / sqrt(σ² + ε), ±clip).
/// μ and σ² are merged batch by batch with Chan et al.'s parallel update, so the result does
/// not depend on how the data was split into batches (up to round-off). The statistics are part
/// of the policy: they are saved in checkpoints and baked into the TorchScript export.
#include <cstdint>
#include <span>
#include <vector>

#include "podium/base/json.h"

namespace podium::learn {

class RunningNormalizer {
 public:
  explicit RunningNormalizer(std::size_t size = 0, double clip = 10.0, double epsilon = 1e-8);

  std::size_t size() const { return mean_.size(); }
  /// Adds `rows` observations stored row-major in `data` (rows × size()).
  void update(std::span<const double> data, std::size_t rows);
  /// Writes the normalised `x` into `out` (both size()).
  void normalize(std::span<const double> x, std::span<float> out) const;

  const std::vector<double>& mean() const { return mean_; }
  const std::vector<double>& variance() const { return var_; }
  /// sqrt(σ² + ε), the divisor used by normalize().
  std::vector<double> scale() const;
  double clip() const { return clip_; }
  double count() const { return count_; }

  base::Json save() const;
  /// Restores save()'s output; throws UserError when the size differs.
  void load(const base::Json& state);

 private:
  std::vector<double> mean_, var_;
  double count_ = 0.0;
  double clip_, epsilon_;
};

}  // namespace podium::learn
