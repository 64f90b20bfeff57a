#include "app/assets.hpp"

#include <cstdlib>
#include <filesystem>

#ifndef APICLAB_ASSETS_DIR
#define APICLAB_ASSETS_DIR "assets"
#endif

namespace apiclab {

namespace fs = std::filesystem;

std::string scenes_directory() {
  if (const char* env = std::getenv("APICLAB_SCENES")) return env;
  fs::path built = fs::path(APICLAB_ASSETS_DIR) / "scenes";
  if (fs::is_directory(built)) return built.string();
  return "assets/scenes";
}

std::string assets_directory() { return fs::path(scenes_directory()).parent_path().string(); }

std::string resolve_scene_path(const std::string& arg) {
  std::error_code ec;  // a path too long to look up is reported by the reader, not thrown here
  if (fs::exists(arg, ec)) return arg;
  if (arg.find('/') == std::string::npos) {
    fs::path p = fs::path(scenes_directory()) /
                 (arg + (fs::path(arg).extension() == ".json" ? "" : ".json"));
    if (fs::exists(p, ec)) return p.string();
  }
  return arg;  // load_scene reports it as missing
}

}  // namespace apiclab
