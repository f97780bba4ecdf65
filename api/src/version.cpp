#include "oer/api/version.hpp"

namespace oer::api {
const char* version() { return kVersion; }
}  // namespace oer::api
