// One registry of string keys for every choice a user makes: the same key is used in scene
// JSON, CLI flags and GUI combo boxes. Numbers have their own registry (parameters.hpp).
#pragma once
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/mpm/kernels.hpp"
#include "sim/scene/message_text.hpp"
#include "sim/scene/scheme_registry.hpp"

namespace apiclab {

enum class Integrator { symplectic, midpoint, backward, lambda_family };
enum class MaterialModel { neo_hookean, fixed_corotated, plastic };
enum class ShapeType { box, ball, annulus, torus, mesh };
enum class SamplingType { lattice, ppc, poisson, triangulated };
enum class BoundaryCondition { slip, sticky, separate, periodic };
enum class DtRule { fixed, cfl, elastic, two_step };
enum class Precision { single, dbl };
// APIC's affine matrix with the multilinear kernel (Sec 5.9).
enum class ApicLinearForm { lagged, bform };
enum class CgPreconditioner { block_jacobi, mass };
// How particles are coloured (render/, the GUI and `render --color`).
enum class ColorMode { speed, material, object, noise };

// A keyed choice: key, value, one-line description for help texts and GUI tooltips.
template <class E>
struct Choice {
  std::string_view key;
  E value;
  std::string_view help;
};

// Built from sim/scene/scheme_registry.hpp: a scheme's key and help are in its own file.
inline const std::vector<Choice<Scheme>>& scheme_choices() {
  static const std::vector<Choice<Scheme>> c = [] {
    std::vector<Choice<Scheme>> v;
    for (const SchemeInfo& s : kSchemes) v.push_back({s.key, s.value, s.help});
    return v;
  }();
  return c;
}
inline const std::vector<Choice<KernelType>>& kernel_choices() {
  static const std::vector<Choice<KernelType>> c = {
      {"linear", KernelType::linear, "multilinear hat; APIC uses the lagged-C form (Sec 5.9)"},
      {"quadratic", KernelType::quadratic, "quadratic B-spline, D_p = dx^2/4"},
      {"cubic", KernelType::cubic, "cubic B-spline, D_p = dx^2/3"}};
  return c;
}
inline const std::vector<Choice<Integrator>>& integrator_choices() {
  static const std::vector<Choice<Integrator>> c = {
      {"symplectic", Integrator::symplectic, "symplectic Euler, lambda = 0 (eqs 27-30)"},
      {"midpoint", Integrator::midpoint, "implicit midpoint, lambda = 1/2 (Sec 4.1)"},
      {"backward", Integrator::backward, "backward Euler (Sec 4.1, E_be), for comparison"},
      {"lambda", Integrator::lambda_family,
       "the lambda-family of eqs 27-30 at solver.lambda (--lambda); stable for every step at "
       "lambda = 1/2 only"}};
  return c;
}
inline const std::vector<Choice<MaterialModel>>& material_choices() {
  static const std::vector<Choice<MaterialModel>> c = {
      {"neo-hookean", MaterialModel::neo_hookean, "compressible neo-Hookean"},
      {"fixed-corotated", MaterialModel::fixed_corotated,
       "fixed corotated (Stomakhin et al. 2012)"},
      {"plastic", MaterialModel::plastic,
       "neo-Hookean elasticity of F_e with multiplicative plastic flow above "
       "materials.*.yield_stress (Fan et al. 2013, Sec 3.7, eqs 34-37)"}};
  return c;
}
inline const std::vector<Choice<ShapeType>>& shape_choices() {
  static const std::vector<Choice<ShapeType>> c = {
      {"box", ShapeType::box, "axis-aligned box: min, max"},
      {"ball", ShapeType::ball, "disk (2D) or sphere (3D): center, radius"},
      {"annulus", ShapeType::annulus, "ring (2D) or hollow cylinder (3D): center, inner, outer"},
      {"torus", ShapeType::torus, "torus: center, inner, outer radius (3D)"},
      {"mesh", ShapeType::mesh, "closed triangle mesh (OBJ): file, scale, translate"}};
  return c;
}
inline const std::vector<Choice<SamplingType>>& sampling_choices() {
  static const std::vector<Choice<SamplingType>> c = {
      {"lattice", SamplingType::lattice, "grid-aligned lattice with a given spacing"},
      {"ppc", SamplingType::ppc, "grid-aligned lattice with N particles per cell"},
      {"poisson", SamplingType::poisson, "Poisson disk (Bridson 2007) with radius and seed"},
      {"triangulated", SamplingType::triangulated,
       "2D box as a regular triangulation, a particle per vertex; F from the mesh (Sec 6.7)"}};
  return c;
}
inline const std::vector<Choice<BoundaryCondition>>& boundary_choices() {
  static const std::vector<Choice<BoundaryCondition>> c = {
      {"slip", BoundaryCondition::slip, "normal velocity set to zero"},
      {"sticky", BoundaryCondition::sticky, "velocity set to zero"},
      {"separate", BoundaryCondition::separate, "normal velocity cannot point into the wall"},
      {"periodic", BoundaryCondition::periodic, "opposite walls identified (domain walls only)"}};
  return c;
}
inline const std::vector<Choice<DtRule>>& dt_rule_choices() {
  static const std::vector<Choice<DtRule>> c = {
      {"fixed", DtRule::fixed, "constant dt (time.dt.value)"},
      {"cfl", DtRule::cfl, "Sec 4.3: nu dx / max(|v_p| + 6 sqrt(d)/dx |B_p|)"},
      {"elastic", DtRule::elastic,
       "explicit limit nu dx / (c + max|v|), c = sqrt((lambda+2mu)/rho)"},
      {"two-step", DtRule::two_step, "Sec 6.7: clamp(nu dx / max(v_max, v_tau), dt_min, dt_max)"}};
  return c;
}
inline const std::vector<Choice<Precision>>& precision_choices() {
  static const std::vector<Choice<Precision>> c = {
      {"double", Precision::dbl, "64-bit (default; conservation tested to round-off)"},
      {"float", Precision::single, "32-bit, faster"}};
  return c;
}

inline const std::vector<Choice<ApicLinearForm>>& apic_linear_form_choices() {
  static const std::vector<Choice<ApicLinearForm>> c = {
      {"lagged", ApicLinearForm::lagged,
       "C = sum v_i grad w_ip^T, the lagged form of Sec 5.9 (default; stable)"},
      {"bform", ApicLinearForm::bform,
       "UNSTABLE: C = B D_p^-1 with the multilinear D_p, singular on grid lines (Sec 5.9)"}};
  return c;
}

inline const std::vector<Choice<CgPreconditioner>>& cg_preconditioner_choices() {
  static const std::vector<Choice<CgPreconditioner>> c = {
      {"block-jacobi", CgPreconditioner::block_jacobi,
       "the inverse of each node's block of the Hessian, translations deflated (default)"},
      {"mass", CgPreconditioner::mass,
       "M^-1: CG in the mass inner product, Algorithm 1 (Sec 4.2)"}};
  return c;
}

inline const std::vector<Choice<ColorMode>>& color_mode_choices() {
  static const std::vector<Choice<ColorMode>> c = {
      {"speed", ColorMode::speed, "particle speed |v_p|"},
      {"material", ColorMode::material, "one colour per material"},
      {"object", ColorMode::object, "one colour per object"},
      {"noise", ColorMode::noise, "|v_p - PIC-interpolated grid velocity|, FLIP's null modes"}};
  return c;
}

template <class E>
std::string choice_keys(const std::vector<Choice<E>>& choices) {
  std::string s;
  for (auto& c : choices) {
    if (!s.empty()) s += '|';
    s += c.key;  // appended, not `"|" + key`: GCC 12 warns falsely (-Wrestrict) on that
  }
  return s;
}

// Throws std::invalid_argument naming the unknown key and the valid ones.
template <class E>
E parse_choice(const std::vector<Choice<E>>& choices, std::string_view key, std::string_view what) {
  for (auto& c : choices)
    if (c.key == key) return c.value;
  // The value quoted short and on one line (fuzz_scene echoed a 3,900-character integrator).
  throw std::invalid_argument("unknown " + std::string(what) + " '" +
                              message_text(std::string(key)) + "' (expected " +
                              choice_keys(choices) + ")");
}

template <class E>
std::string_view choice_key(const std::vector<Choice<E>>& choices, E value) {
  for (auto& c : choices)
    if (c.value == value) return c.key;
  return "?";
}

inline std::string_view key_of(Scheme s) { return choice_key(scheme_choices(), s); }
inline std::string_view key_of(KernelType k) { return choice_key(kernel_choices(), k); }
inline std::string_view key_of(Integrator i) { return choice_key(integrator_choices(), i); }
inline std::string_view key_of(MaterialModel m) { return choice_key(material_choices(), m); }
inline std::string_view key_of(BoundaryCondition b) { return choice_key(boundary_choices(), b); }
inline std::string_view key_of(DtRule r) { return choice_key(dt_rule_choices(), r); }
inline std::string_view key_of(Precision p) { return choice_key(precision_choices(), p); }
inline std::string_view key_of(CgPreconditioner c) {
  return choice_key(cg_preconditioner_choices(), c);
}
inline std::string_view key_of(ApicLinearForm f) {
  return choice_key(apic_linear_form_choices(), f);
}
inline std::string_view key_of(ColorMode m) { return choice_key(color_mode_choices(), m); }

}  // namespace apiclab
