#pragma once
// Checked command-line numbers for the benches: a flag or a typo read by atoi would run the
// bench with 0 and print figures of nothing.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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

/// Whether `text` is JSON; parsed into `value` when it is (a typo then gets the usage, not an
/// uncaught parse_error).
template <class Json>
bool json_value(const char* text, Json& value) {
  if (!Json::accept(text)) return false;
  value = Json::parse(text);
  return true;
}

/// Whether `text` is a comma-separated list whose items each pass `item(text, value)`, with no
/// empty item ("1,,2" and "1," are typos); the values in `values`.
template <class T, class Item>
bool list(const std::string& text, std::vector<T>& values, Item&& item) {
  values.clear();
  for (std::size_t from = 0;;) {
    const std::size_t comma = text.find(',', from);
    const std::string piece = text.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    if (piece.empty() || !item(piece.c_str(), values.emplace_back())) return false;
    if (comma == std::string::npos) return true;
    from = comma + 1;
  }
}

/// A list item that is any non-empty text (a name).
inline bool name(const char* text, std::string& value) {
  value = text;
  return true;
}

/// How one `--flag value` pair read.
enum class Flag { read, bad_value, unknown };
inline Flag checked(bool ok) { return ok ? Flag::read : Flag::bad_value; }

/// Reads argv[1..] as `--flag value` pairs, each through `read(key, value)` → Flag. On a flag
/// without a value, an unknown flag or a bad value: prints "ARGV0: what" and "usage: ARGV0 USAGE"
/// and returns false (the bench then exits 2).
template <class Read>
bool read_flags(int argc, char** argv, const char* usage, Read&& read) {
  const auto fail = [&](const std::string& error) {
    std::fprintf(stderr, "%s: %s\nusage: %s %s\n", argv[0], error.c_str(), argv[0], usage);
    return false;
  };
  for (int i = 1; i < argc; i += 2) {
    const std::string key = argv[i];
    if (i + 1 == argc) return fail("no value after " + key);
    switch (read(key, argv[i + 1])) {
      case Flag::read:
        break;
      case Flag::unknown:
        return fail("unknown option " + key);
      case Flag::bad_value:
        return fail("bad value '" + std::string(argv[i + 1]) + "' for " + key);
    }
  }
  return true;
}

}  // namespace podium::bench
