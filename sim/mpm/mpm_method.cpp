// The MPM solver family as a registered method: its constructor (dimension × precision) and
// the validation of its keys in the scene's `solver` section.
#include "sim/method_registry.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/scene/memory_estimate.hpp"

namespace apiclab {
namespace {

std::unique_ptr<Simulation> make_mpm(const SceneDesc& scene, Precision precision) {
  check_memory(scene, precision);  // before the grid and the particles are allocated
  const bool single = precision == Precision::single;
  if (scene.dim == 2)
    return single ? std::unique_ptr<Simulation>(new MpmSimulation<float, 2>(scene))
                  : std::unique_ptr<Simulation>(new MpmSimulation<double, 2>(scene));
  return single ? std::unique_ptr<Simulation>(new MpmSimulation<float, 3>(scene))
                : std::unique_ptr<Simulation>(new MpmSimulation<double, 3>(scene));
}

// The words and numbers are read by now (the registries' keys of method mpm); ranges are checked
// once, for every method, by validate() (sim/scene/parameters.hpp). What is left is how they
// combine.
void validate_mpm(SceneSection& r, SceneDesc& s) {
  const auto& v = s.solver;
  if (v.kernel == KernelType::linear && s.time.rule == DtRule::cfl)  // see sim/time_step_rules.hpp
    r.fail("kernel",
           "the 'cfl' time-step rule needs the quadratic or cubic kernel (Sec 4.3 bounds D_p^-1 "
           "(x_i - x_p) "
           "only when D_p = k dx^2 I; Sec 5.9)");
  if (v.scheme == Scheme::polypic && v.polypic_modes > polypic::full_modes(s.dim))
    r.fail("polypic_modes", "PolyPIC has " + std::to_string(polypic::full_modes(s.dim)) +
                                " modes in " + std::to_string(s.dim) + "D (got " +
                                std::to_string(v.polypic_modes) + ")");
  if (const std::string why = scheme_conflict(v); !why.empty()) r.fail("scheme", why);
}

}  // namespace

std::string scheme_conflict(const SolverDesc& v) {
  if (v.scheme == Scheme::polypic && v.kernel != KernelType::quadratic)
    return "polypic needs the quadratic kernel (its modes are Fu et al. 2017's basis for the "
           "quadratic B-spline, 3 per axis): set solver.kernel to quadratic (--kernel quadratic)";
  if (v.scheme != Scheme::mls) return "";
  if (v.kernel == KernelType::linear)
    return "mls needs the quadratic or cubic kernel (its force uses D_p^-1 = 1/(k dx^2)): set "
           "solver.kernel to quadratic (--kernel quadratic)";
  if (v.integrator != Integrator::symplectic)
    return "mls runs with the symplectic integrator only (Hu et al. 2018's explicit form): set "
           "solver.integrator to symplectic (--integrator symplectic)";
  return "";
}

SolverMethod mpm_method() {
  return {"mpm", "Material Point Method with PIC/FLIP/APIC/RPIC transfers (Jiang et al. 2017)",
          make_mpm, validate_mpm};
}

}  // namespace apiclab
