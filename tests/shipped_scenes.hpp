// The path of a scene shipped in assets/scenes, for tests that load one by name.
#pragma once
#include <string>

namespace apiclab::test {

inline std::string shipped_scene_path(const std::string& name) {
  return std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/" + name + ".json";
}

}  // namespace apiclab::test
