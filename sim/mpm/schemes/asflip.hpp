// ASFLIP (Fei et al. 2021; the update of the authors' demo pyasflip, G2P of Substep): APIC's
// affine transfers plus α times the particle's own FLIP difference, and a position correction
// β α (v_p − v_old^PIC) for separating particles.
#pragma once
#include <algorithm>
#include <cmath>

#include "sim/mpm/schemes/apic.hpp"

namespace apiclab::schemes {

struct Asflip : Apic {
  static constexpr std::string_view key = "asflip", name = "ASFLIP";
  static constexpr std::string_view help =
      "ASFLIP (Fei et al. 2021; the update of the authors' demo pyasflip, G2P of Substep): "
      "APIC's affine transfers, v <- v^PIC + alpha (v_p - "
      "v_old^PIC) with alpha = solver.flip_alpha, x <- x + dt (v^PIC + beta alpha (v_p - "
      "v_old^PIC)) for separating particles, beta = solver.asflip_beta (beta = 0: the plain "
      "APIC/FLIP blend)";
  static constexpr std::string_view source = "Fei et al. 2021 (update of their demo pyasflip)";
  static constexpr std::string_view conserves = "mass, linear momentum; not angular momentum";
  static constexpr int colour = 5;
  static constexpr bool reads_old = true;
  static constexpr bool corrects_move = true;

  // APIC's v^PIC and C plus α (v_p^n − Σ w v_i^n), v_i^n from APIC's affine P2G; α = 0 is APIC.
  template <class G, class T, class Inertia, class V, class M>
  static void update(const G& g, T alpha, bool /*lagged*/, Inertia&&, V& v, M& C) {
    v = g.pic + alpha * (v - g.old);
    C = g.apic_C;
  }

  // Separating particles also move by Δt β α (v_p^n − v_old); a particle whose volume shrinks
  // this step (ln J^{n+1} < −10⁻³, the threshold of pyasflip) keeps the grid's motion (β_min = 0).
  template <class T, class V, class M>
  static void correct_move(V& move, const M& F_next, const V& v_n, const V& v_old, T dt, T alpha,
                           T beta) {
    if (beta != T(0) && std::log(std::max(F_next.determinant(), T(1e-15))) >= T(-1e-3))
      move += (dt * beta * alpha) * (v_n - v_old);
  }
};

}  // namespace apiclab::schemes
