// Which solver method a scene runs, read before the scene is loaded, so that the command line
// can tell an option of another method from an error in the file (docs/cli.md).
#pragma once
#include <string>
#include <vector>

namespace apiclab {

struct SceneMethod {
  std::string file_method;             // the file's solver.method ("mpm" when it names none)
  std::string method;                  // after the `--set` overrides
  std::vector<std::string> file_keys;  // the file's solver keys besides `method`
  // The MPM choices after the overrides, as written ("" when the scene leaves the default).
  std::string scheme, kernel, integrator;
};

// The scene file's method before and after `overrides`; both empty when the file cannot be read
// or parsed (loading it reports why).
SceneMethod scene_method(const std::string& path, const std::vector<std::string>& overrides);

}  // namespace apiclab
