// This build's version: CMake's project() version and `git describe` at configure time
// (version.cpp, the one file that the configure step's definitions reach).
#pragma once
#include <string>

namespace apiclab {

// The version string of this build ("unknown" when the build did not define one).
std::string apiclab_version();

namespace cli {
std::string version_text();  // "apiclab 0.1.0 (git 1fbbf76-dirty)"
}  // namespace cli

}  // namespace apiclab
