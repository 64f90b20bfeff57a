// A scheme named with its parameter, for people: every label of a pane or a run (GUI pane
// titles and plot legends, compare PNGs and terminal lines, figure legends, sweep tables, the
// CSV sidecar's "label") says XPIC(3) or PolyPIC(9 modes), not XPIC or PolyPIC, so two runs of
// one scheme with different parameters are told apart. Machine-readable columns keep the bare
// registry key (the output contract, docs/outputs.md#contract) and carry the parameter beside it.
#pragma once
#include <cstdio>
#include <string>

#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/scene/registry.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

// The scene-wide numbers that complete a scheme's name; a live scheme switch keeps them.
struct SchemeParameters {
  int xpic_order = 2;      // XPIC's m (Hammerquist and Nairn 2017)
  int polypic_modes = 9;   // PolyPIC's kept modes, solver.polypic_modes resolved (0 = all)
  double asflip_beta = 1;  // ASFLIP's position correction β (Fei et al. 2021)
};

inline SchemeParameters scheme_parameters_of(const SceneDesc& s) {
  return {s.solver.xpic_order, polypic::kept_modes(s.solver.polypic_modes, s.dim),
          s.solver.asflip_beta};
}

// The parameter of a scheme that has one: "3" (XPIC's m), "9 modes" (PolyPIC), "α=0.9 β=1"
// (ASFLIP's blend and position correction), "α=0.9" (FLIP's blend of eq 3, below 1 only: 1 is
// FLIP itself); "" for the others. `ascii` writes a and b for α and β (Dear ImGui's default font
// has no Greek).
inline std::string scheme_parameter(Scheme s, double flip_alpha, const SchemeParameters& p,
                                    bool ascii = false) {
  char buf[64];
  switch (s) {
    case Scheme::xpic:
      std::snprintf(buf, sizeof buf, "%d", p.xpic_order);
      return buf;
    case Scheme::polypic:
      std::snprintf(buf, sizeof buf, "%d mode%s", p.polypic_modes, p.polypic_modes == 1 ? "" : "s");
      return buf;
    case Scheme::flip:
      if (flip_alpha >= 1) return "";
      std::snprintf(buf, sizeof buf, "%s=%.3g", ascii ? "a" : "\u03B1", flip_alpha);
      return buf;
    case Scheme::asflip:
      std::snprintf(buf, sizeof buf, "%s=%.3g %s=%.3g", ascii ? "a" : "\u03B1", flip_alpha,
                    ascii ? "b" : "\u03B2", p.asflip_beta);
      return buf;
    default:
      return "";
  }
}

// `name` ("xpic", "XPIC", "PolyPIC", ...) followed by "(parameter)" when the scheme has one.
inline std::string with_scheme_parameter(std::string name, Scheme s, double flip_alpha,
                                         const SchemeParameters& p, bool ascii = false) {
  const std::string parameter = scheme_parameter(s, flip_alpha, p, ascii);
  return parameter.empty() ? name : name + "(" + parameter + ")";
}

// The grid update with the λ it runs: "midpoint", "backward", "lambda(0.3)" (solver.lambda is
// read by the lambda integrator only, so no other label hides a λ).
inline std::string integrator_label(const SolverDesc& s) {
  if (s.integrator != Integrator::lambda_family) return std::string(key_of(s.integrator));
  char buf[48];
  std::snprintf(buf, sizeof buf, "lambda(%.3g)", s.integrator_lambda());
  return buf;
}

// A run's name in terminal lines and sidecars: "xpic(3)", "apic", or the solver method ("eol").
inline std::string run_label(const SceneDesc& s) {
  if (s.solver.method != "mpm") return s.solver.method;
  return with_scheme_parameter(std::string(key_of(s.solver.scheme)), s.solver.scheme,
                               s.solver.flip_alpha, scheme_parameters_of(s));
}

}  // namespace apiclab
