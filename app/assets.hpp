// Asset discovery: where the shipped scenes and meshes are. The app decides (environment,
// then the build-time path, then ./assets); the solver library only takes resolved paths.
#pragma once
#include <string>

namespace apiclab {

// The folder holding scenes/ and meshes/: $APICLAB_SCENES/.. when set, else the build-time
// path, else ./assets.
std::string assets_directory();
// The folder holding the shipped scenes: $APICLAB_SCENES, else assets_directory()/scenes.
std::string scenes_directory();
// Resolves a scene argument: a path, or a bare name like `rotating-disk`.
std::string resolve_scene_path(const std::string& arg);

}  // namespace apiclab
