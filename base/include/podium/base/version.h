#pragma once
/// The version stamp recorded with every campaign and checked by the plugin loader.
namespace podium::base {

/// Podium's release version, e.g. "0.1.0".
const char* version();
/// The compiler that built this binary, e.g. "GCC 12.2.0".
const char* compiler_id();
/// CMake build type the binary was configured with.
const char* build_type();

}  // namespace podium::base
