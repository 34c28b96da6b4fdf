#pragma once
/// JSON helpers shared by every folder: one JSON library (nlohmann/json) and one way to read
/// typed fields with errors that name the JSON path.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace podium::base {

using Json = nlohmann::json;

/// Reads and parses a JSON file; throws UserError "FILE: invalid JSON at line L column C: MESSAGE"
/// on failure, including arrays and objects nested deeper than 100 levels (configs need a handful).
Json read_json_file(const std::filesystem::path& path);

/// Writes JSON atomically (temporary file in the same folder, then rename).
void write_json_file_atomic(const std::filesystem::path& path, const Json& value);

/// "stages[1].search.budget"-style path building for error messages.
std::string json_path_join(const std::string& parent, const std::string& key);
std::string json_path_index(const std::string& parent, std::size_t index);

}  // namespace podium::base
