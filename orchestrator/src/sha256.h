#pragma once
// SHA-256 of a file (OpenSSL's EVP), recorded with every artifact.
#include <filesystem>
#include <string>

namespace podium::orchestrator {

/// Lower-case hex digest; throws base::RuntimeError when the file cannot be read.
std::string sha256_file(const std::filesystem::path& path);

}  // namespace podium::orchestrator
