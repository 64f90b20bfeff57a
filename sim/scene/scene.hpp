// Scene description: everything a paper scene states, as plain data read from JSON
// (docs/architecture.md, Scenes). All values are double; the solver converts to its scalar type.
// A number or a word a scene file sets has its default in its registry alone
// (sim/scene/parameters.cpp, sim/scene/choice_parameters.cpp): SceneDesc() starts from it. A
// material, object or collider built in code starts as the registry's default says (a test holds
// them equal).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/scene/registry.hpp"

namespace apiclab {

using Vec3d = std::array<double, 3>;

// A scene that cannot be used: the message names the file and the JSON key.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct DomainDesc {
  Vec3d min{}, max{};
  double dx{};
  // Walls in the order x-, x+, y-, y+, z-, z+.
  std::array<BoundaryCondition, 6> walls{};
  bool periodic(int axis) const { return walls[2 * axis] == BoundaryCondition::periodic; }
};

struct TimeDesc {
  double end{};
  double fps{};
  DtRule rule{};
  double dt{};      // fixed rule: the step; other rules: an upper bound
  double nu{};      // Courant number for cfl, elastic and two-step rules
  double dt_min{};  // two-step rule (Sec 6.7)
  double v_tau{};   // two-step rule (Sec 6.7)
  // Fixed rule: the step is honoured exactly and a frame is the step at or just past its time;
  // land_on_frames shortens the steps that would pass a frame time instead. The adaptive rules
  // always land on frame times.
  bool land_on_frames{};
  bool lands_on_frames() const { return rule != DtRule::fixed || land_on_frames; }
};

// The Eulerian-on-Lagrangian methods' keys of the `solver` section (sim/eol/eol_method.cpp).
struct EolSolverDesc {
  double alpha{};        // advection Courant bound of eq 30 (Fan et al. 2013, Sec 3.6)
  int padding{};         // eol: empty cells around the rest shape in its grid
  double cell{};         // eol: the objects' cell size; 0 = domain.dx
  double grid_extent{};  // eol: side of each object's grid; 0 = rest shape + padding
  // Contact with walls and colliders (sim/eol/contact/surface_contact.hpp): the surface rows of eqs
  // 27-28, one per collision cell of side contact_cell (0 = the grid cell), or one row per node
  // on or behind a plane.
  enum class Contact { surface, nodes };
  Contact contact{};
  double contact_cell{};
  // The elastic forces on each object's grid: explicit (the paper's, Sec 5) or backward Euler
  // (sim/eol/grid/implicit_elasticity.hpp), which lifts the elastic cap on the step.
  enum class Elasticity { explicit_euler, backward_euler };
  Elasticity elasticity{};
};

struct SolverDesc {
  std::string method;  // the solver family (sim/method_registry.hpp); the keys below are MPM's
  Scheme scheme{};
  double flip_alpha{};  // eq 3 blend: 1 = pure FLIP, 0 = PIC
  // ASFLIP (Fei et al. 2021): the position correction β for separating particles; 0 = the plain
  // APIC/FLIP blend.
  double asflip_beta{};
  int xpic_order{};  // XPIC(m) (Hammerquist and Nairn 2017): m ≥ 1, XPIC(1) = PIC
  KernelType kernel{};
  Integrator integrator{};
  // Multilinear kernel only: APIC's C as lagged Σ ṽ ∇wᵀ or as the unstable B D_p⁻¹ (Sec 5.9).
  ApicLinearForm apic_linear_form{};
  // PolyPIC (Fu et al. 2017): modes kept per velocity component, 0 = all (9 in 2D, 27 in 3D).
  int polypic_modes{};
  std::optional<double> lambda;  // λ of eqs 27-30 for the lambda integrator only
  double newton_tolerance{};
  int newton_max_iterations{};
  double cg_tolerance{};
  int cg_max_iterations{};
  CgPreconditioner preconditioner{};
  bool stop_on_nonconvergence{};
  // solver.ledger: each step's row carries its stages' changes (DiagnosticsRow::stages).
  bool ledger{};
  double blowup_energy_factor{};
  // solver.max_memory_gb: cap on the estimated memory (sim/scene/memory_estimate.hpp); empty: the
  // machine's available memory (--max-memory none sets it to 1e300).
  std::optional<double> max_memory_gb;
  // Scenes with fewer particles run their loops on one thread (an OpenMP region costs more
  // than it saves there). Not a scene key: tests set it to 0 to exercise the parallel paths.
  std::size_t parallel_min_particles = 20000;
  EolSolverDesc eol;  // read only for solver.method eol or eulerian
  // The λ of eqs 27-30 the step runs: 0 symplectic Euler, ½ midpoint, solver.lambda for the
  // lambda integrator (½ until one is given); backward Euler moves the grid as λ = 0 does
  // (x̃ = x + Δt ṽ), so its transfers are λ = 0's.
  double integrator_lambda() const {
    switch (integrator) {
      case Integrator::midpoint:
        return 0.5;
      case Integrator::lambda_family:
        return lambda.value_or(0.5);
      default:
        return 0.0;
    }
  }
};

struct MaterialDesc {
  std::string name;
  MaterialModel model = MaterialModel::neo_hookean;
  // The scene must give all three; these make a usable material for scenes built in code.
  double E = 1000.0, nu = 0.3, rho = 1.0;
  double viscosity = 0.0;  // Kelvin-Voigt η (eol, eulerian)
  // The plastic model's ‖σ_y‖ (required by it, refused by the others) and flow rate ν (eq 37).
  std::optional<double> yield_stress;
  double flow_rate = 1.0;
  double mu() const { return E / (2.0 * (1.0 + nu)); }
  double lambda() const { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
  double wave_speed() const { return std::sqrt((lambda() + 2.0 * mu()) / rho); }
};

struct ShapeDesc {
  ShapeType type = ShapeType::box;
  Vec3d min{0, 0, 0}, max{0, 0, 0};  // box
  Vec3d center{0, 0, 0};             // ball, annulus, torus
  double radius = 0, inner = 0, outer = 0;
  Vec3d axis{0, 0, 1};  // annulus (3D cylinder axis) and torus symmetry axis
  double length = 0;    // annulus in 3D: cylinder length
  std::string file;     // mesh: OBJ path, relative to the scene file
  double scale = 1.0;   // mesh
  Vec3d translate{0, 0, 0};
  Vec3d rotation_axis{0, 0, 1};  // rotation about `center` (mesh: about origin, then translate)
  double rotation_degrees = 0;
  // rotation.random_seed: when >= 0, rotation_degrees was drawn from it, uniform in [0, 360).
  std::int64_t rotation_seed = -1;
};

struct SamplingDesc {
  SamplingType type = SamplingType::ppc;
  double spacing = 0;  // lattice, triangulated (vertex spacing)
  double ppc = 4;      // particles per cell
  double radius = 0;   // poisson: minimum separation
  std::uint64_t seed = 1;
};

struct ObjectDesc {
  std::string name;
  ShapeDesc shape;
  int material = 0;
  SamplingDesc sampling;
  Vec3d velocity{0, 0, 0};
  Vec3d angular_velocity{0, 0, 0};  // about the shape's center; 2D uses z
  // Zero-length penalty springs f = −c (x_p − x_p⁰) on the vertex rows named here
  // ("top", "bottom", "left", "right"; triangulated objects, Sec 6.7).
  std::vector<std::string> anchors;
  double anchor_stiffness = 1e5;
};

enum class ColliderType { plane, box, rod };

// One key of a collider's path: at time t the body's reference point is `point` and it has
// turned by `degrees` from its start (about z in 2D, about the collider's axis in 3D).
struct ColliderKey {
  double t = 0;
  Vec3d point{0, 0, 0};
  double degrees = 0;
};

// A prescribed rigid body (sim/geometry/collider_body.hpp places it at a time): a plane through
// `point`, or a box or rod (capsule) around `point`; it moves with a constant velocity and
// angular velocity, or along `path`, linearly between its keys.
struct ColliderDesc {
  Vec3d point{0, 0, 0};   // a plane's point; a box's or rod's center
  Vec3d normal{0, 1, 0};  // points into the free side
  BoundaryCondition condition = BoundaryCondition::slip;
  Vec3d velocity{0, 0, 0};  // constant, with angular_velocity, unless a path is given
  ColliderType type = ColliderType::plane;
  Vec3d size{0.2, 0.2, 0.2};        // box: edge lengths along its own axes
  double radius = 0.05;             // rod
  double length = 0.4;              // rod: its segment's length, along its own x axis
  double degrees = 0;               // box, rod: the start's turn about z (2D) or `axis` (3D)
  Vec3d axis{0, 0, 1};              // 3D: the axis of `degrees` and of the path's turns
  Vec3d angular_velocity{0, 0, 0};  // about `point`; 2D uses z
  std::vector<ColliderKey> path;    // times strictly increasing; empty: constant motion
};

struct SceneDesc {
  SceneDesc();  // every number and word at its registry default (sim/scene/parameters.cpp)
  std::string name, description;
  std::string source;  // file it came from, for messages and relative paths
  // Where relative mesh files are looked for after the scene's own folder and its parent
  // (the app adds its asset folder; sim does no discovery of its own).
  std::vector<std::string> asset_dirs;
  int dim = 2;
  DomainDesc domain;
  Vec3d gravity{};
  TimeDesc time;
  SolverDesc solver;
  std::vector<MaterialDesc> materials;
  std::vector<ObjectDesc> objects;
  std::vector<ColliderDesc> colliders;
};

// A section of the scene file as a method's validate hook sees it (sim/method_registry.hpp):
// strict, so a key left unread is an error, and every failure is one SceneError line naming the
// file and key. Its numbers are read from the registry before the hook runs.
class SceneSection {
 public:
  virtual ~SceneSection() = default;
  virtual bool has(const std::string& key) const = 0;
  virtual bool boolean(const std::string& key, bool fallback) = 0;
  virtual std::string string(const std::string& key, const std::string& fallback) = 0;
  // "file: key 'solver.KEY'", the prefix of every error about that key.
  virtual std::string where(const std::string& key) const = 0;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(where(key) + ": " + what);
  }
  template <class E>
  E choice(const std::string& key, const std::vector<Choice<E>>& choices, E fallback,
           const char* what) {
    if (!has(key)) return fallback;
    const std::string s = string(key, "");
    try {
      return parse_choice(choices, s, what);
    } catch (const std::invalid_argument& e) {
      fail(key, e.what());
    }
  }
};

// Reads a scene file, applies `--set KEY=VALUE` overrides (JSON paths like
// `materials.0.E`), and validates it (numbers through sim/scene/parameters.hpp's registry).
// Throws SceneError naming file and key.
SceneDesc load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
// Same, from JSON text (tests, GUI).
SceneDesc parse_scene_text(const std::string& json_text, const std::string& source_name,
                           const std::vector<std::string>& overrides = {});

}  // namespace apiclab
