#include "sim/scene/parameters.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/layout_parameters.hpp"

namespace apiclab {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr Range kPositive{0, kInf, true, true};
constexpr Range kAnyReal{-kInf, kInf, true, true};
constexpr Range kUnit{0, 1, false, false};
constexpr Range kAtLeastOne{1, kInf, false, true};

int material_count(const SceneDesc& s) { return int(s.materials.size()); }
int dim_count(const SceneDesc& s) { return s.dim; }

std::vector<NumericParameter> declare() {
  using S = SceneDesc;
  return {
      // Domain and grid.
      {.key = "domain.dx",
       .label = "grid spacing dx",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .help = "grid cell width (Sec 3); the kernels span 2-4 cells",
       .get = [](const S& s, int) { return s.domain.dx; },
       .set = [](S& s, int, double v) { s.domain.dx = v; }},
      {.key = "domain.min.*",
       .label = "domain min",
       .unit = "m",
       .range = kAnyReal,
       .required = true,
       .help = "lower corner of the grid domain, one component per axis",
       .get = [](const S& s, int i) { return s.domain.min[size_t(i)]; },
       .set = [](S& s, int i, double v) { s.domain.min[size_t(i)] = v; },
       .count = dim_count},
      {.key = "domain.max.*",
       .label = "domain max",
       .unit = "m",
       .range = kAnyReal,
       .required = true,
       .help = "upper corner of the grid domain; must exceed domain.min on every axis",
       .get = [](const S& s, int i) { return s.domain.max[size_t(i)]; },
       .set = [](S& s, int i, double v) { s.domain.max[size_t(i)] = v; },
       .count = dim_count},
      {.key = "gravity.*",
       .label = "gravity",
       .unit = "m/s^2",
       .range = kAnyReal,
       .help = "body acceleration, one component per axis (explicit force of eq 29)",
       .get = [](const S& s, int i) { return s.gravity[size_t(i)]; },
       .set = [](S& s, int i, double v) { s.gravity[size_t(i)] = v; },
       .count = dim_count},
      // Time.
      {.key = "time.end",
       .label = "end time",
       .unit = "s",
       .range = kPositive,
       .default_value = 1.0,
       .help = "simulated time to run",
       .get = [](const S& s, int) { return s.time.end; },
       .set = [](S& s, int, double v) { s.time.end = v; }},
      {.key = "time.fps",
       .label = "frames per second",
       .unit = "1/s",
       .range = kPositive,
       .default_value = 24.0,
       .help = "output frames per simulated second; every frame time is landed on exactly",
       .get = [](const S& s, int) { return s.time.fps; },
       .set = [](S& s, int, double v) { s.time.fps = v; }},
      {.key = "time.dt.value",
       .label = "time step dt",
       .unit = "s",
       .range = kPositive,
       .default_value = 1e30,
       .help = "fixed rule: the step, taken exactly (required; a frame is the step at or just "
               "past its time); other rules: an upper bound dt_max (default none; two-step: "
               "0.005, Sec 6.7)",
       .get = [](const S& s, int) { return s.time.dt; },
       .set = [](S& s, int, double v) { s.time.dt = v; },
       .required_for = [](const S& s) { return s.time.rule == DtRule::fixed; },
       .default_for = [](const S& s) { return s.time.rule == DtRule::two_step ? 0.005 : 1e30; }},
      {.key = "time.dt.nu",
       .label = "Courant number nu",
       .unit = "1",
       .range = kPositive,
       .default_value = 0.5,
       .help = "CFL fraction of the cfl (Sec 4.3), elastic and two-step (Sec 6.7) rules; eol and "
               "eulerian cap their elastic step with it under elastic, with at most 0.3 under "
               "cfl and two-step",
       .get = [](const S& s, int) { return s.time.nu; },
       .set = [](S& s, int, double v) { s.time.nu = v; }},
      {.key = "time.dt.min",
       .label = "minimum time step dt_min",
       .unit = "s",
       .range = kPositive,
       .default_value = 1e-6,
       .help = "two-step rule: lower clamp of dt (Sec 6.7)",
       .get = [](const S& s, int) { return s.time.dt_min; },
       .set = [](S& s, int, double v) { s.time.dt_min = v; }},
      {.key = "time.dt.v_tau",
       .label = "speed floor v_tau",
       .unit = "m/s",
       .range = kPositive,
       .default_value = 0.01,
       .help = "two-step rule: dt = nu dx / max(v_max, v_tau) (Sec 6.7)",
       .get = [](const S& s, int) { return s.time.v_tau; },
       .set = [](S& s, int, double v) { s.time.v_tau = v; }},
      // Solver.
      {.key = "solver.flip_alpha",
       .label = "FLIP blend alpha",
       .unit = "1",
       .range = kUnit,
       .default_value = 1.0,
       .help = "FLIP/PIC blend of eq 3: 1 = pure FLIP, 0 = PIC (used by the flip scheme)",
       .get = [](const S& s, int) { return s.solver.flip_alpha; },
       .set = [](S& s, int, double v) { s.solver.flip_alpha = v; },
       .method = "mpm"},
      {.key = "solver.asflip_beta",
       .label = "ASFLIP position correction beta",
       .unit = "1",
       .range = kUnit,
       .default_value = 1.0,
       .help = "ASFLIP (Fei et al. 2021): x_p += dt beta alpha (v_p - v_old^PIC) for "
               "separating particles (ln J > -1e-3); 0 = the plain APIC/FLIP blend (used by the "
               "asflip scheme)",
       .get = [](const S& s, int) { return s.solver.asflip_beta; },
       .set = [](S& s, int, double v) { s.solver.asflip_beta = v; },
       .method = "mpm"},
      {.key = "solver.xpic_order",
       .label = "XPIC order m",
       .unit = "1",
       .range = {1, 1000, false, false},
       .default_value = 2,
       .integer = true,
       .help = "XPIC(m) (Hammerquist and Nairn 2017): terms of the series in the "
               "particle-grid-particle operator; 1 = PIC, m - 1 extra grid passes (used by the "
               "xpic scheme)",
       .get = [](const S& s, int) { return double(s.solver.xpic_order); },
       .set = [](S& s, int, double v) { s.solver.xpic_order = int(std::min(v, 1e9)); },
       .method = "mpm"},
      {.key = "solver.polypic_modes",
       .label = "PolyPIC modes",
       .unit = "1",
       .range = Range{0, 27, false, false},
       .default_value = 0,
       .integer = true,
       .help = "PolyPIC (Fu et al. 2017): velocity modes kept per component, 0 = all (9 in 2D, 27 "
               "in 3D); 1 = PIC, 3 (2D) / 4 (3D) = APIC's affine",
       .get = [](const S& s, int) { return double(s.solver.polypic_modes); },
       .set = [](S& s, int, double v) { s.solver.polypic_modes = int(v); },
       .method = "mpm"},
      {.key = "solver.lambda",
       .label = "integrator lambda",
       .unit = "1",
       .range = kUnit,
       .default_value = 0.0,
       .help = "lambda of eqs 27-30 for solver.integrator lambda, which alone reads it (0 is "
               "symplectic Euler, 1/2 midpoint, 1 explicit, not backward Euler); stable for every "
               "dt at 1/2 alone, others up to about dx / (2 c |1 - 2 lambda|)",
       .get = [](const S& s, int) { return s.solver.integrator_lambda(); },
       .set = [](S& s, int, double v) { s.solver.lambda = v; },
       .is_set = [](const S& s, int) { return s.solver.lambda.has_value(); },
       .method = "mpm"},
      {.key = "solver.newton_tolerance",
       .label = "Newton tolerance",
       .unit = "1",
       .range = kPositive,
       .default_value = 1e-6,
       .help = "implicit solve (Sec 4.1): stop when |grad E| < tol * reference speed",
       .get = [](const S& s, int) { return s.solver.newton_tolerance; },
       .set = [](S& s, int, double v) { s.solver.newton_tolerance = v; },
       .method = "mpm"},
      {.key = "solver.newton_max_iterations",
       .label = "Newton iteration cap",
       .unit = "1",
       .range = kAtLeastOne,
       // A converging step stops at its tolerance, so the cap decides only where it would not:
       // ringing's first backward Euler step at 16x the explicit limit takes 31 damped iterations.
       .default_value = 50,
       .integer = true,
       .help = "implicit solve (Sec 4.1): Newton steps before giving up (a converging step stops "
               "at its tolerance first)",
       .get = [](const S& s, int) { return double(s.solver.newton_max_iterations); },
       .set = [](S& s, int, double v) { s.solver.newton_max_iterations = int(std::min(v, 1e9)); },
       .method = "mpm"},
      {.key = "solver.cg_tolerance",
       .label = "CG tolerance",
       .unit = "1",
       .range = kPositive,
       .default_value = 1e-6,
       .help = "implicit solve's CG (Sec 4.2): relative residual (M^-1 norm) to stop at",
       .get = [](const S& s, int) { return s.solver.cg_tolerance; },
       .set = [](S& s, int, double v) { s.solver.cg_tolerance = v; },
       .method = "mpm"},
      {.key = "solver.cg_max_iterations",
       .label = "CG iteration cap",
       .unit = "1",
       .range = kAtLeastOne,
       .default_value = 200,
       .integer = true,
       .help = "implicit solve's CG (Sec 4.2): iterations per Newton step",
       .get = [](const S& s, int) { return double(s.solver.cg_max_iterations); },
       .set = [](S& s, int, double v) { s.solver.cg_max_iterations = int(std::min(v, 1e9)); },
       .method = "mpm"},
      {.key = "solver.blowup_energy_factor",
       .label = "blow-up energy factor",
       .unit = "1",
       .range = kPositive,
       .default_value = 10.0,
       .help = "a run fails when kinetic + elastic energy exceeds this multiple of its reference",
       .get = [](const S& s, int) { return s.solver.blowup_energy_factor; },
       .set = [](S& s, int, double v) { s.solver.blowup_energy_factor = v; }},
      {.key = "solver.max_memory_gb",
       .label = "memory cap",
       .unit = "GB",
       .range = kPositive,
       .default_value = 1e30,  // unused: unset means the available memory (unset_default)
       .help = "refuse a scene whose estimated grid and particle memory exceeds this (1 GB = 1e9 "
               "bytes; --max-memory overrides it)",
       .get = [](const S& s, int) { return s.solver.max_memory_gb.value_or(0); },
       .set = [](S& s, int, double v) { s.solver.max_memory_gb = v; },
       .is_set = [](const S& s, int) { return s.solver.max_memory_gb.has_value(); },
       .unset_default = "the available memory"},
      // Eulerian-on-Lagrangian methods (sim/eol/, Fan et al. 2013).
      {.key = "solver.alpha",
       .label = "advection Courant alpha",
       .unit = "1",
       .range = Range{0, 1, true, true},
       .default_value = 0.5,
       .help = "eol, eulerian: dt max|v*|/dx <= alpha for the advection (Fan et al. 2013, eqs "
               "30, 33)",
       .get = [](const S& s, int) { return s.solver.eol.alpha; },
       .set = [](S& s, int, double v) { s.solver.eol.alpha = v; },
       .method = "eol eulerian"},
      {.key = "solver.contact_cell",
       .label = "collision cell",
       .unit = "m",
       .range = Range{0, kInf, false, true},
       .default_value = 0,
       .help = "eol, eulerian with solver.contact surface: side of the collision grid along a "
               "plane, one contact row per cell (Fan et al. 2013, Sec 3.5); 0 = the grid cell",
       .get = [](const S& s, int) { return s.solver.eol.contact_cell; },
       .set = [](S& s, int, double v) { s.solver.eol.contact_cell = v; },
       .method = "eol eulerian"},
      {.key = "solver.padding",
       .label = "grid padding",
       .unit = "1",
       .range = Range{0, 1000, false, false},
       .default_value = 3,
       .integer = true,
       .help = "eol: empty cells around the rest shape's bounds in its object grid",
       .get = [](const S& s, int) { return double(s.solver.eol.padding); },
       .set = [](S& s, int, double v) { s.solver.eol.padding = int(v); },
       .method = "eol"},
      {.key = "solver.cell",
       .label = "object cell size",
       .unit = "m",
       .range = Range{0, kInf, false, true},
       .default_value = 0,
       .help = "eol: cell size of the object grids; 0 takes domain.dx",
       .get = [](const S& s, int) { return s.solver.eol.cell; },
       .set = [](S& s, int, double v) { s.solver.eol.cell = v; },
       .method = "eol"},
      {.key = "solver.grid_extent",
       .label = "object grid extent",
       .unit = "m",
       .range = Range{0, kInf, false, true},
       .default_value = 0,
       .help = "eol: side of each object's grid (a square or cube about the rest shape); 0 = the "
               "rest shape's bounds plus the padding",
       .get = [](const S& s, int) { return s.solver.eol.grid_extent; },
       .set = [](S& s, int, double v) { s.solver.eol.grid_extent = v; },
       .method = "eol"},
      // Materials.
      {.key = "materials.*.E",
       .label = "Young's modulus E",
       .unit = "Pa",
       .range = kPositive,
       .required = true,
       .help = "stiffness; with nu gives the Lame parameters mu = E/(2(1+nu)), lambda = E "
               "nu/((1+nu)(1-2nu))",
       .get = [](const S& s, int i) { return s.materials[size_t(i)].E; },
       .set = [](S& s, int i, double v) { s.materials[size_t(i)].E = v; },
       .count = material_count},
      {.key = "materials.*.nu",
       .label = "Poisson's ratio nu",
       .unit = "1",
       .range = Range{-1, 0.5, true, true},
       .required = true,
       .help = "compressibility; the Lame lambda diverges at 0.5 (incompressible) and mu at -1",
       .get = [](const S& s, int i) { return s.materials[size_t(i)].nu; },
       .set = [](S& s, int i, double v) { s.materials[size_t(i)].nu = v; },
       .count = material_count},
      {.key = "materials.*.rho",
       .label = "density rho",
       .unit = "kg/m^2",
       .unit_3d = "kg/m^3",
       .range = kPositive,
       .required = true,
       .help = "mass per area (2D) or volume (3D); particle mass m_p = rho V_p",
       .get = [](const S& s, int i) { return s.materials[size_t(i)].rho; },
       .set = [](S& s, int i, double v) { s.materials[size_t(i)].rho = v; },
       .count = material_count},
      {.key = "materials.*.viscosity",
       .label = "viscosity eta",
       .unit = "Pa s",
       .range = Range{0, kInf, false, true},
       .default_value = 0,
       .help = "eol, eulerian: Kelvin-Voigt damping, a viscous stress eta (grad v + grad v^T) "
               "beside the elastic one; damps deformation, not rigid motion",
       .get = [](const S& s, int i) { return s.materials[size_t(i)].viscosity; },
       .set = [](S& s, int i, double v) { s.materials[size_t(i)].viscosity = v; },
       .count = material_count,
       .method = "eol eulerian"},
      {.key = "materials.*.yield_stress",
       .label = "yield stress sigma_y",
       .unit = "Pa",
       .range = kPositive,
       .help = "plastic model: the norm of the deviatoric Cauchy stress sigma above which F_p "
               "flows (Fan et al. 2013, eq 37)",
       .get = [](const S& s, int i) { return s.materials[size_t(i)].yield_stress.value_or(kInf); },
       .set = [](S& s, int i, double v) { s.materials[size_t(i)].yield_stress = v; },
       .count = material_count,
       .is_set = [](const S& s, int i) { return s.materials[size_t(i)].yield_stress.has_value(); },
       .unset_default = "none: the plastic model requires it"},
      {.key = "materials.*.flow_rate",
       .label = "plastic flow rate nu",
       .unit = "1",
       .range = Range{0, 1, true, false},
       .default_value = 1,
       .help = "plastic model: gamma = nu (norm(sigma) - sigma_y) / norm(sigma) in [0, 1], the "
               "share of the deviatoric elastic stretch a step moves into F_p (Fan et al. 2013, "
               "eq 37); 1 returns the stress to the yield surface",
       .get = [](const S& s, int i) { return s.materials[size_t(i)].flow_rate; },
       .set = [](S& s, int i, double v) { s.materials[size_t(i)].flow_rate = v; },
       .count = material_count},
  };
}

[[noreturn]] void fail(const SceneDesc& s, const std::string& key, const std::string& what) {
  throw SceneError(s.source + ": key '" + key + "': " + what);
}

// What relates several values: only meaningful once each is in range.
void validate_domain(const SceneDesc& s) {
  const DomainDesc& d = s.domain;
  for (int a = 0; a < s.dim; ++a)
    if (!(d.max[a] > d.min[a])) fail(s, "domain.max", "must exceed min on every axis");
  for (int a = 0; a < s.dim; ++a) {
    const double cells = (d.max[a] - d.min[a]) / d.dx;
    // Node indices are ints; the memory guard (sim/scene/memory_estimate.hpp) refuses far less.
    if (cells > 1e9) fail(s, "domain.dx", "domain has more than 1e9 cells along an axis");
    if (d.periodic(a) && std::abs(cells - std::round(cells)) > 1e-6 * cells)
      fail(s, "domain.dx", "a periodic axis must be a whole number of cells long");
  }
}

// solver.lambda belongs to the lambda integrator alone: symplectic and midpoint are the family's
// λ = 0 and λ = ½, backward Euler is not of the family (Sec 4.1), so a λ beside them would either
// be ignored or turn the run into another integrator under their name.
void validate_integrator(const SceneDesc& s) {
  if (s.solver.method != "mpm") return;
  const bool family = s.solver.integrator == Integrator::lambda_family;
  if (s.solver.lambda && !family)
    fail(s, "solver.lambda",
         "applies to solver.integrator lambda only (solver.integrator " +
             std::string(key_of(s.solver.integrator)) +
             (s.solver.integrator == Integrator::backward   ? " is not of the lambda family"
              : s.solver.integrator == Integrator::midpoint ? " is lambda = 1/2"
                                                            : " is lambda = 0") +
             "; give solver.integrator lambda, or leave solver.lambda out)");
  if (family && !s.solver.lambda)
    fail(s, "solver.integrator", "lambda needs solver.lambda (--lambda), the lambda of eqs 27-30");
}

// Frame numbers are ints (app/frame_loop.hpp); a billion frames is far past any real run.
void validate_time(const SceneDesc& s) {
  const double frames = s.time.end * s.time.fps;
  if (frames > 1e9)
    fail(s, "time.end",
         "end time x fps = " + format_value(frames) +
             " frames, more than 1e9 (lower time.end or time.fps)");
}

}  // namespace

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::text() const {
  return std::string(lo_open ? "(" : "[") + format_value(lo) + ", " + format_value(hi) +
         (hi_open ? ")" : "]");
}

std::string format_value(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;  // shortest round-trip form
  return std::string(buf, end);
}

std::string NumericParameter::key_at(int index) const {
  std::string k(key);
  const auto star = k.find('*');
  if (star != std::string::npos) k.replace(star, 1, std::to_string(index));
  return k;
}

std::string NumericParameter::unit_for(int dim) const {
  return std::string(dim == 3 && !unit_3d.empty() ? unit_3d : unit);
}

std::string NumericParameter::default_text() const {
  if (required) return "required";
  if (is_set) return unset_default.empty() ? "from the integrator" : std::string(unset_default);
  if (default_value >= 1e30) return "none";
  return format_value(default_value);
}

std::string NumericParameter::describe() const {
  // "unit: s", or "dimensionless": a bare "1" would read as a value.
  std::string u = unit == "1" ? "dimensionless" : "unit: " + std::string(unit);
  if (!unit_3d.empty()) u += " (2D), " + std::string(unit_3d) + " (3D)";
  return std::string(help) + " [" + u + "; allowed: " + range.text() +
         (integer ? ", integer" : "") + "; default: " + default_text() + "]";
}

bool method_listed(std::string_view methods, std::string_view solver_method) {
  if (methods.empty()) return true;
  for (std::size_t at = 0; at <= methods.size();) {
    const std::size_t end = std::min(methods.find(' ', at), methods.size());
    if (methods.substr(at, end - at) == solver_method) return true;
    at = end + 1;
  }
  return false;
}

bool NumericParameter::read_by(std::string_view solver_method) const {
  return method_listed(method, solver_method);
}

const std::vector<NumericParameter>& numeric_parameters() {
  static const std::vector<NumericParameter> all = declare();
  return all;
}

bool key_matches(std::string_view pattern, std::string_view key, int* index) {
  const auto star = pattern.find('*');
  if (star == std::string_view::npos) {
    if (key != pattern) return false;
    if (index) *index = 0;
    return true;
  }
  const std::string_view head = pattern.substr(0, star), tail = pattern.substr(star + 1);
  if (key.size() <= head.size() + tail.size() || key.substr(0, head.size()) != head ||
      key.substr(key.size() - tail.size()) != tail)
    return false;
  const std::string_view middle = key.substr(head.size(), key.size() - head.size() - tail.size());
  if (middle == "*") {
    if (index) *index = 0;
    return true;
  }
  if (middle.find_first_not_of("0123456789") != std::string_view::npos || middle.size() > 6)
    return false;
  if (index) *index = std::stoi(std::string(middle));
  return true;
}

const NumericParameter* find_parameter(std::string_view key, int* index) {
  for (const auto& p : numeric_parameters())
    if (key_matches(p.key, key, index)) return &p;
  return nullptr;
}

std::optional<std::string> parameter_error(const NumericParameter& p, int index, double value,
                                           const std::string& file) {
  const bool whole = !p.integer || value == std::floor(value);
  if (p.range.contains(value) && whole) return std::nullopt;
  return file + ": key '" + p.key_at(index) + "': " + std::string(p.label) + " " +
         format_value(value) + " is outside the allowed range " + p.range.text() +
         (p.integer ? " (integers)" : "");
}

// Numbers, words and the dimension start at the registries' defaults; an optional key (is_set)
// starts unset.
SceneDesc::SceneDesc() {
  for (const NumericParameter& p : numeric_parameters()) {
    if (p.is_set) continue;
    const int n = p.count ? p.count(*this) : 1;
    for (int i = 0; i < n; ++i) p.set(*this, i, p.default_value);
  }
  for (const ChoiceParameter& c : choice_parameters())
    if (c.key.find('*') == std::string_view::npos) c.set(*this, 0, c.default_key);
  for (const LayoutParameter& l : layout_parameters())
    if (l.key.find('*') == std::string_view::npos) l.set(*this, 0, {l.default_value});
}

void validate(const SceneDesc& s) {
  for (const auto& p : numeric_parameters()) {
    const int n = p.count ? p.count(s) : 1;
    for (int i = 0; i < n; ++i) {
      if (p.is_set && !p.is_set(s, i)) continue;
      if (auto e = parameter_error(p, i, p.get(s, i), s.source)) throw SceneError(*e);
    }
  }
  validate_domain(s);
  validate_time(s);
  validate_integrator(s);
}

void apply_parameter(SceneDesc& scene, std::string_view key, double value) {
  int index = 0;
  const NumericParameter* p = find_parameter(key, &index);
  if (!p)
    throw SceneError(scene.source + ": key '" + std::string(key) + "': not a numeric parameter");
  if (p->count && (index < 0 || index >= p->count(scene)))
    throw SceneError(scene.source + ": key '" + std::string(key) + "' does not exist");
  if (auto e = parameter_error(*p, index, value, scene.source)) throw SceneError(*e);
  SceneDesc edited = scene;
  p->set(edited, index, value);
  validate(edited);
  scene = std::move(edited);
}

}  // namespace apiclab
