// An immutable picture of one simulation at one time: what the renderer draws and the GUI
// shows (DESIGN.md, Threads). Produced by the simulation owner, shared as shared_ptr<const>.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "diagnostics.hpp"
#include "scene.hpp"

namespace apiclab {

// Why a run stopped: which step, what time, which quantity.
struct Failure {
  long step = 0;
  double t = 0;
  std::string quantity;  // e.g. "total energy", "non-finite velocity"
  std::string message;   // one line for the user
};

struct Snapshot {
  int dim = 2;
  long step = 0;
  double time = 0;
  std::string scene_name, scheme, kernel, integrator;
  double flip_alpha = 1;
  // Per particle, in a stable order (particle id), dim floats each.
  std::vector<float> positions, velocities;
  std::vector<float> noise;  // |v_p − Σ w_ip v_i| after a fresh P2G: FLIP's null modes (may be empty)
  std::vector<std::int32_t> material, object;
  std::vector<float> radius;  // drawing radius per particle (half the sampling spacing)
  // The scene's frame of reference.
  Vec3d domain_min{0, 0, 0}, domain_max{0, 0, 0};
  double dx = 0;
  std::vector<ColliderDesc> colliders;
  std::vector<std::string> material_names;
  // Diagnostics rows since the start of the run (the GUI plots them).
  std::vector<DiagnosticsRow> diagnostics;
  std::optional<Failure> failure;
  std::size_t count() const { return dim ? positions.size() / size_t(dim) : 0; }
};

}  // namespace apiclab
