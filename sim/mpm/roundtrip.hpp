// The round-trip transfer error probe of Jiang et al. 2017, Sec 6.8 (Fig 11), measured on the
// solver's own G2P and P2G (through MpmProbe, sim/mpm/probe.hpp), not on a copy of them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene/registry.hpp"

namespace apiclab {

struct RoundTripResult {
  int resolution = 0;  // grid cells per axis over [0, 2π]
  double dx = 0;
  double l2_error = 0;  // ‖v_i^after − v_i^before‖ in the discrete L2 norm (Σ |e_i|² Δx²)^½
  std::size_t particles = 0;
};

// Periodic [0, 2π]², Poisson disk particles with minimum separation Δx/3, grid velocity
// (1.1 sin x, 0.9 cos y); the solver's G2P then P2G with Δt = 0. Any scheme but those that
// blend with a prior particle velocity (std::invalid_argument for flip, asflip or a resolution
// below 4); xpic_order is XPIC's m.
// "" when the probe runs `scheme`, else why not (one line).
std::string roundtrip_refusal(Scheme scheme);
RoundTripResult roundtrip_error(KernelType kernel, Scheme scheme, int resolution,
                                std::uint64_t seed = 1, int xpic_order = 2);

}  // namespace apiclab
