// `apiclab --version`: CMake's project() version and `git describe` at configure time
// (app/CMakeLists.txt passes both to this file alone, so a new commit recompiles only it).
#include "app/version.hpp"

#include <string>

#ifndef APICLAB_VERSION
#define APICLAB_VERSION "unknown"
#endif
#ifndef APICLAB_GIT_DESCRIBE
#define APICLAB_GIT_DESCRIBE ""
#endif

namespace apiclab {

std::string apiclab_version() {
  const std::string git = APICLAB_GIT_DESCRIBE;
  return std::string(APICLAB_VERSION) + (git.empty() ? "" : " (git " + git + ")");
}

namespace cli {
std::string version_text() { return "apiclab " + apiclab_version(); }
}  // namespace cli

}  // namespace apiclab
