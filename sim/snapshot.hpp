// An immutable picture of one simulation at one time: what the renderer draws and the GUI
// shows (docs/architecture.md, Threads). Produced by the simulation owner, shared as
// shared_ptr<const>.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

// Why a run stopped: which step, what time, which quantity.
struct Failure {
  long step = 0;
  double t = 0;
  std::string quantity;  // e.g. "total energy", "non-finite velocity"
  std::string message;   // one line for the user
};

// A grid that carries values at its nodes, in a frame of its own: node (i, j, k) sits at
// world x = R (dx (i, j, k)) + t. Solvers with moving grids (Eulerian-on-Lagrangian) fill
// these; the renderer draws each grid's outline and colours its nodes by one field.
struct GridLayer {
  struct Field {
    std::string name;
    std::vector<float> values;  // one per node, i fastest, then j, then k
  };
  std::string name;
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // R, row-major, orthonormal
  Vec3d translation{0, 0, 0};                                 // t: world position of node 0
  std::array<int, 3> nodes{1, 1, 1};                          // per axis (2D: nodes[2] = 1)
  double dx = 0;
  std::vector<Field> fields;
  std::size_t node_count() const { return std::size_t(nodes[0]) * nodes[1] * nodes[2]; }
};

// An object's surface placed in space (Eulerian-on-Lagrangian, Fan et al. 2013 Sec 3.8): dim
// floats per vertex for positions and velocities, and dim vertex indices per element
// (segments in 2D, triangles counter-clockwise from outside in 3D).
struct SurfaceLayer {
  std::string name;
  std::vector<float> positions, velocities;
  std::vector<std::uint32_t> elements;
};

struct Snapshot {
  int dim = 2;
  long step = 0;
  double time = 0;
  std::string scene_name, scheme, kernel, integrator;
  double flip_alpha = 1;  // FLIP's blend (eq 3); labels show it for the FLIP scheme only
  SchemeParameters scheme_parameters;  // XPIC's m, PolyPIC's modes, ASFLIP's β, for labels
  // Per particle, in a stable order (particle id), dim floats each.
  std::vector<float> positions, velocities;
  // |v_p − Σ w_ip v_i| after a fresh P2G: FLIP's null modes (may be empty).
  std::vector<float> noise;
  std::vector<std::int32_t> material, object;
  std::vector<float> radius;  // drawing radius per particle (half the sampling spacing)
  // The scene's frame of reference.
  Vec3d domain_min{0, 0, 0}, domain_max{0, 0, 0};
  double dx = 0;
  std::vector<ColliderDesc> colliders;
  std::vector<std::string> material_names;
  std::vector<std::string> object_names;  // the scene's, by object index ("" when unnamed)
  std::vector<GridLayer> grids;           // optional grid layers (none for the MPM solvers)
  std::vector<SurfaceLayer> surfaces;     // optional object surfaces (none for the MPM solvers)
  std::optional<Failure> failure;
  std::size_t count() const { return dim ? positions.size() / size_t(dim) : 0; }
};

}  // namespace apiclab
