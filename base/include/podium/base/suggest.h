#pragma once
/// Names near a mistyped one, for error lines: `no campaign "getup_demo" (did you mean getup-demo?)`,
/// an unknown task or spec key. Used by the plugin loader, the store and the orchestrator.
#include <string>
#include <vector>

namespace podium::base {

/// The names of `known` nearest to `wanted` by edit distance (letter case ignored, "-" and "_"
/// the same), at most 3, nearest first; only those within a third of wanted's length (at least 2).
std::vector<std::string> nearest_names(const std::string& wanted, const std::vector<std::string>& known);

/// " (did you mean a or b?)", or "" when no name is near.
std::string did_you_mean(const std::string& wanted, const std::vector<std::string>& known);

/// "a, b, c" ("none" when empty).
std::string name_list(const std::vector<std::string>& names);

}  // namespace podium::base
