// Material points, structure-of-arrays: one array per quantity, no per-particle allocation.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/math.hpp"

namespace apiclab {

template <class T, int D>
struct Particles {
  std::vector<Vec<T, D>> x, v;  // position, velocity
  std::vector<Mat<T, D>> C;     // affine velocity matrix C_p = B_p D_p⁻¹ (zero for PIC/FLIP)
  std::vector<Mat<T, D>> F;     // deformation gradient
  std::vector<T> mass, volume0;
  std::vector<std::int32_t> material, object, id;  // id: stable order for dumps and snapshots
  // PolyPIC's mode coefficients beyond the affine ones, one array per mode
  // (sim/mpm/schemes/polypic_modes.hpp); empty for every other scheme.
  std::vector<std::vector<Vec<T, D>>> modes;
  // F_p⁻¹ per particle for the plastic model (sim/plasticity.hpp; F then holds F_e); empty
  // in a scene without one.
  std::vector<Mat<T, D>> fp_inv;

  // Allocates `count` zeroed mode arrays (0 frees them).
  void set_mode_count(std::size_t count) {
    modes.resize(count);
    modes.shrink_to_fit();
    for (auto& m : modes) m.assign(size(), Vec<T, D>::Zero());
  }

  std::size_t size() const { return x.size(); }
  // Bytes the arrays hold (their capacity, PolyPIC's modes included), for state_bytes().
  std::size_t allocated_bytes() const {
    std::size_t b =
        (x.capacity() + v.capacity()) * sizeof(Vec<T, D>) +
        (C.capacity() + F.capacity() + fp_inv.capacity()) * sizeof(Mat<T, D>) +
        (mass.capacity() + volume0.capacity()) * sizeof(T) +
        (material.capacity() + object.capacity() + id.capacity()) * sizeof(std::int32_t) +
        modes.capacity() * sizeof(modes[0]);
    for (const auto& m : modes) b += m.capacity() * sizeof(Vec<T, D>);
    return b;
  }
  void resize(std::size_t n) {
    x.resize(n);
    v.resize(n);
    C.resize(n);
    F.resize(n);
    mass.resize(n);
    volume0.resize(n);
    material.resize(n);
    object.resize(n);
    id.resize(n);
    for (auto& m : modes) m.resize(n, Vec<T, D>::Zero());
    if (!fp_inv.empty()) fp_inv.resize(n, Mat<T, D>::Identity());
  }
  // out[k] = this[order[k]] for every array; `out` keeps its capacity between calls.
  void gather_into(const std::vector<std::uint32_t>& order, Particles& out,
                   [[maybe_unused]] bool parallel = false) const {
    if (out.modes.size() != modes.size()) out.modes.resize(modes.size());
    out.resize(order.size());
    const std::ptrdiff_t n = std::ptrdiff_t(order.size());
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      std::uint32_t s = order[k];
      out.x[k] = x[s];
      out.v[k] = v[s];
      out.C[k] = C[s];
      out.F[k] = F[s];
      out.mass[k] = mass[s];
      out.volume0[k] = volume0[s];
      out.material[k] = material[s];
      out.object[k] = object[s];
      out.id[k] = id[s];
    }
    for (std::size_t j = 0; j < modes.size(); ++j)
#pragma omp parallel for schedule(static) if (parallel)
      for (std::ptrdiff_t k = 0; k < n; ++k) out.modes[j][k] = modes[j][order[k]];
    out.fp_inv.resize(fp_inv.empty() ? 0 : order.size());
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(out.fp_inv.size()); ++k)
      out.fp_inv[k] = fp_inv[order[k]];
  }
};

}  // namespace apiclab
