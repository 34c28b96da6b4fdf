#include "podium/base/version.h"

namespace podium::base {

const char* version() { return PODIUM_VERSION_STRING; }
const char* compiler_id() { return PODIUM_COMPILER_STRING; }
const char* build_type() { return PODIUM_BUILD_TYPE_STRING; }

}  // namespace podium::base
