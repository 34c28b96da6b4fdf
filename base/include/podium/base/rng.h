#pragma once
/// Seeded random numbers. There is no global generator: every component owns an Rng seeded from
/// the run record, and its whole state serialises to a string so a resumed search continues the
/// same stream.
#include <cstdint>
#include <random>
#include <string>

namespace podium::base {

class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0) : engine_(seed) {}

  double uniform(double low = 0.0, double high = 1.0) { return std::uniform_real_distribution<double>(low, high)(engine_); }
  double normal(double mean = 0.0, double stddev = 1.0) { return std::normal_distribution<double>(mean, stddev)(engine_); }
  /// Uniform integer in [low, high].
  std::int64_t integer(std::int64_t low, std::int64_t high) {
    return std::uniform_int_distribution<std::int64_t>(low, high)(engine_);
  }
  std::uint64_t next() { return engine_(); }
  std::mt19937_64& engine() { return engine_; }

  /// The full generator state as text (std::mt19937_64's stream format).
  std::string save() const;
  /// Restores a state produced by save(); throws UserError on malformed text.
  void load(const std::string& state);

 private:
  std::mt19937_64 engine_;
};

/// Derives an independent seed from a parent seed and a path of indices (SplitMix64 mixing), so
/// trial seeds depend only on (campaign seed, stage, trial index), never on scheduling order.
std::uint64_t derive_seed(std::uint64_t parent, std::uint64_t a, std::uint64_t b = 0);

}  // namespace podium::base
