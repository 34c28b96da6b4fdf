#pragma once
// Checked command-line numbers for the benches: a flag or a typo read by atoi would run the
// bench with 0 and print figures of nothing.
#include <cmath>
#include <cstdlib>

namespace podium::bench {

/// Whether `text` is a whole decimal number ≥ `min` and nothing else; the number in `value`.
inline bool whole_number(const char* text, long long min, long long& value) {
  char* end = nullptr;
  value = std::strtoll(text, &end, 10);
  return end != text && *end == '\0' && value >= min;
}

/// Whether `text` is a whole decimal number in [min, max] and nothing else; the number in `value`
/// (an int: `max` keeps it in range).
inline bool count(const char* text, long long min, long long max, int& value) {
  long long v = 0;
  if (!whole_number(text, min, v) || v > max) return false;
  value = static_cast<int>(v);
  return true;
}

/// Whether `text` is a finite decimal number and nothing else; the number in `value`.
inline bool real_number(const char* text, double& value) {
  char* end = nullptr;
  value = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(value);
}

}  // namespace podium::bench
