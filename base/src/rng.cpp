#include "podium/base/rng.h"

#include <sstream>

#include "podium/base/error.h"

namespace podium::base {

std::string Rng::save() const {
  std::ostringstream out;
  out << engine_;
  return out.str();
}

void Rng::load(const std::string& state) {
  std::istringstream in(state);
  std::mt19937_64 engine;
  in >> engine;
  if (in.fail()) throw UserError("rng: malformed generator state (" + std::to_string(state.size()) + " characters)");
  engine_ = engine;
}

namespace {
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
}  // namespace

std::uint64_t derive_seed(std::uint64_t parent, std::uint64_t a, std::uint64_t b) {
  return splitmix64(splitmix64(splitmix64(parent) ^ a) ^ b);
}

}  // namespace podium::base
