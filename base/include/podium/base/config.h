#pragma once
/// The one reader of config objects: learner configs, search configs, the campaign spec and every
/// task's config. Typed reads with defaults, ranges and allowed values, nested objects and
/// arrays, unknown keys rejected, and every error one line naming the JSON path, the value and
/// the rule:
///   spec.json: stages[0].config.family: "plateus" is not one of basins, plateaus, voronoi
/// The code that reads a config also describes it: run on a describing reader
/// (ConfigReader::describe) every read records its key, type, default, range and choices and
/// returns the default, so `podium tasks` and the dashboard show exactly what is validated.
#include <cstdint>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "podium/base/error.h"
#include "podium/base/json.h"

namespace podium::base {

/// A config value that a reader rejected. path(): its JSON path inside the config that was read
/// ("" for that config itself); problem(): the value and the rule. what() is
/// "SOURCE: PATH: PROBLEM" (without the parts that are empty).
class ConfigError : public UserError {
 public:
  ConfigError(const std::string& source, const std::string& path, const std::string& problem);
  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string path_, problem_;
};

/// The interval a number must lie in: [min, max], or (min, max] with exclusive_min.
struct Interval {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool exclusive_min = false;
};

/// The interval an integer must lie in, [min, max]; reads also clamp it to the result type.
struct IntInterval {
  std::int64_t min = std::numeric_limits<std::int64_t>::min();
  std::int64_t max = std::numeric_limits<std::int64_t>::max();
};

/// Pass `required` in place of a default to make a key required.
struct Required {};
inline constexpr Required required{};

class ConfigReader {
 public:
  /// Reads the JSON object `config` (kept by reference: it must outlive the reader). `path` names
  /// it in errors ("stages[0].search.config"; "" for a whole file or a task's config) and
  /// `source` (a file name, "ppo config") comes first in them.
  ConfigReader(const Json& config, std::string path, std::string source = "");
  ConfigReader(Json&&, std::string, std::string = "") = delete;  // would dangle

  /// Reads the whole of `config` (path "") with `read(ConfigReader&)`, then finish(): a task's
  /// config in one call. Returns what `read` returns.
  template <class Read>
  static auto parse(const Json& config, std::string source, Read&& read) {
    ConfigReader r(config, "", std::move(source));
    auto value = read(r);
    r.finish();
    return value;
  }

  /// What `read(reader)` accepts: `read` runs once on a describing reader, on which every read
  /// returns its default (a required key: a placeholder) and validates nothing, and an array of
  /// objects runs its element reader once. The description is a list of keys:
  ///   [{"key", "type": "boolean"|"integer"|"number"|"string"|"array"|"object"|"any", "default"?,
  ///     "required"?, "min"?, "max"?, "exclusive_min"?, "choices"?, "doc"?,
  ///     "items"? (an array's element: {"type", "min"?, ... , "keys"?}), "keys"? (an object's)}]
  template <class F>
  static Json describe(F&& read) {
    ConfigReader reader;
    read(reader);
    return reader.description();
  }
  /// The description of `describe` turned into {key: default} (keys without a default left out).
  static Json defaults(const Json& description);

  bool boolean(const std::string& key, bool fallback, const std::string& doc = "");
  template <class T>
  T integer(const std::string& key, T fallback, IntInterval range = {}, const std::string& doc = "") {
    return static_cast<T>(read_integer(key, static_cast<std::int64_t>(fallback), false, clamped<T>(range), doc));
  }
  template <class T>
  T integer(const std::string& key, Required, IntInterval range = {}, const std::string& doc = "") {
    return static_cast<T>(read_integer(key, 0, true, clamped<T>(range), doc));
  }
  double number(const std::string& key, double fallback, Interval range = {}, const std::string& doc = "");
  double number(const std::string& key, Required, Interval range = {}, const std::string& doc = "");
  /// An absent key gives `fallback`; a present one may be "".
  std::string string(const std::string& key, const std::string& fallback, const std::string& doc = "");
  /// A required string must not be empty.
  std::string string(const std::string& key, Required, const std::string& doc = "");
  /// A file path: a string described with "format": "file", so `podium submit` resolves a relative
  /// one against the spec's folder, checks that the file exists and passes it on absolute.
  std::string file(const std::string& key, const std::string& fallback, const std::string& doc = "");
  std::string file(const std::string& key, Required, const std::string& doc = "");
  /// file(), and a value that is not "" must name a regular file now (also for a config that did
  /// not pass through `podium submit`): a warm start's checkpoint, say.
  std::string existing_file(const std::string& key, const std::string& fallback, const std::string& doc = "");
  /// A file or folder path ("format": "path"): resolved and checked by `podium submit` as file() is.
  std::string path(const std::string& key, const std::string& fallback, const std::string& doc = "");
  std::string choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed,
                     const std::string& doc = "");
  std::string choice(const std::string& key, Required, const std::vector<std::string>& allowed, const std::string& doc = "");

  template <class T>
  std::vector<T> integers(const std::string& key, const std::vector<T>& fallback, IntInterval range = {},
                          const std::string& doc = "") {
    const auto values = read_integers(key, std::vector<std::int64_t>(fallback.begin(), fallback.end()), clamped<T>(range), doc);
    return std::vector<T>(values.begin(), values.end());
  }
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback, Interval range = {},
                              const std::string& doc = "");
  std::vector<std::string> strings(const std::string& key, const std::vector<std::string>& fallback, const std::string& doc = "");

  /// Reads `field` with its current value as the default, by its type (bool, integer, floating
  /// point, string, or a vector of those); for plain config structs read field by field.
  template <class T>
  void field(const std::string& key, T& field);

  /// A nested object read by `read(child)`, its unknown keys rejected; absent: an empty object.
  template <class F>
  auto object(const std::string& key, F&& read, const std::string& doc = "") {
    ConfigReader child = enter_object(key, false, doc);
    return finished(child, read);
  }
  template <class F>
  auto object(const std::string& key, Required, F&& read, const std::string& doc = "") {
    ConfigReader child = enter_object(key, true, doc);
    return finished(child, read);
  }
  /// An array of objects, each read by `read(child)`; absent: an empty array. Returns the
  /// results of `read`, one per element (nothing if `read` returns void). On a describing
  /// reader `read` runs once, on a describing element, and the result is empty.
  template <class F>
  auto objects(const std::string& key, F&& read, const std::string& doc = "") {
    using Result = std::invoke_result_t<F&, ConfigReader&>;
    std::vector<ConfigReader> children = enter_array(key, doc);
    if constexpr (std::is_void_v<Result>) {
      for (auto& child : children) finished(child, read);
    } else {
      std::vector<Result> results;
      for (auto& child : children) {
        if (child.describing_) finished(child, read);
        else results.push_back(finished(child, read));
      }
      return results;
    }
  }
  /// A JSON object handed on unread (e.g. a task config, checked by the task); absent: {}.
  Json raw_object(const std::string& key, const std::string& doc = "");
  /// A required value of any type, for a key that takes one of several shapes (read it again
  /// with the typed read for its shape).
  Json raw(const std::string& key, Required, const std::string& doc = "");

  /// Whether the config has `key` (false on a describing reader).
  bool has(const std::string& key) const;
  /// Throws ConfigError at `key` (its JSON path), with its value if present, then `rule`.
  [[noreturn]] void fail(const std::string& key, const std::string& rule) const;
  /// The same for element `index` of the array at `key` ("stage[1]: \"x\" is ...").
  [[noreturn]] void fail(const std::string& key, std::size_t index, const std::string& rule) const;
  /// Throws ConfigError for the first key that no read asked for, naming the keys that were read.
  void finish() const;
  /// The JSON path of `key` in errors, e.g. "stages[0].search.config.k".
  std::string path_of(const std::string& key) const;
  /// The keys read so far, described as `describe` does.
  Json description() const;

 private:
  struct Node;
  ConfigReader();  // describing
  ConfigReader(const Json* config, std::string path, std::string source, std::shared_ptr<Node> node, bool describing);

  template <class T>
  static IntInterval clamped(IntInterval range) {
    static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>);
    constexpr auto lo = std::numeric_limits<T>::min();
    constexpr auto hi = std::numeric_limits<T>::max();
    if (static_cast<long double>(range.min) < static_cast<long double>(lo)) range.min = static_cast<std::int64_t>(lo);
    if (static_cast<long double>(range.max) > static_cast<long double>(hi)) range.max = static_cast<std::int64_t>(hi);
    return range;
  }
  template <class F>
  static auto finished(ConfigReader& child, F& read) {
    if constexpr (std::is_void_v<std::invoke_result_t<F&, ConfigReader&>>) {
      read(child);
      child.finish();
    } else {
      auto result = read(child);
      child.finish();
      return result;
    }
  }

  std::int64_t read_integer(const std::string& key, std::int64_t fallback, bool is_required, IntInterval range,
                            const std::string& doc);
  std::vector<std::int64_t> read_integers(const std::string& key, const std::vector<std::int64_t>& fallback, IntInterval range,
                                          const std::string& doc);
  double read_number(const std::string& key, double fallback, bool is_required, Interval range, const std::string& doc);
  std::string read_choice(const std::string& key, const std::string& fallback, bool is_required,
                          const std::vector<std::string>& allowed, const std::string& doc);
  ConfigReader enter_object(const std::string& key, bool is_required, const std::string& doc);
  // One reader per element, or (describing) one describing element.
  std::vector<ConfigReader> enter_array(const std::string& key, const std::string& doc);
  // Marks `key` read, records its description (once) and returns its value, or null if absent;
  // a required absent key throws.
  const Json* take(const std::string& key, bool is_required, const Json& info, const std::string& doc,
                   std::shared_ptr<Node> child = nullptr);
  [[noreturn]] void fail_at(const std::string& path, const std::string& problem) const;

  const Json* config_;
  std::string path_, source_;
  std::shared_ptr<Node> node_;
  bool describing_;
  std::set<std::string> read_;
};

template <class T>
void ConfigReader::field(const std::string& key, T& field) {
  if constexpr (std::is_same_v<T, bool>) field = boolean(key, field);
  else if constexpr (std::is_integral_v<T>) field = integer<T>(key, field);
  else if constexpr (std::is_floating_point_v<T>) field = static_cast<T>(number(key, field));
  else if constexpr (std::is_same_v<T, std::string>) field = string(key, field);
  else if constexpr (std::is_same_v<T, std::vector<std::string>>) field = strings(key, field);
  else if constexpr (std::is_same_v<T, std::vector<double>>) field = numbers(key, field);
  else field = integers<typename T::value_type>(key, field);
}

}  // namespace podium::base
