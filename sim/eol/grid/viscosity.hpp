// Kelvin–Voigt damping on an object's grid (materials.*.viscosity η; not in Fan et al. 2013): a
// viscous Cauchy stress σ_v = η (∇_y v + ∇_y vᵀ) beside the elastic one, integrated at the same
// 2^d Gauss points, f_k = −Σ_q V_q σ_v ∇_y N_k(ξ_q) with the current volume V_q = Δx^d w H.
// σ_v is symmetric and vanishes for a rigid velocity (∇v skew), so it damps deformation only and
// exerts no net force or torque; its power −Σ V_q 2η |sym ∇v|² is never positive.
#pragma once
#include <cstddef>
#include <vector>

#include "sim/eol/grid/cell_points.hpp"
#include "sim/eol/grid/forces.hpp"

namespace apiclab::eol {

template <class T, int D>
class ViscousForces {
  static constexpr int P = 1 << D;

 public:
  std::size_t bytes() const { return held_bytes(force) + held_bytes(corner_); }
  // Whether any material has η > 0 (else compute() is never called and holds nothing).
  static bool any(const std::vector<ElasticMaterial<T>>& materials) {
    for (const auto& m : materials)
      if (m.viscosity > T(0)) return true;
    return false;
  }
  // force: per node, frame axes, from the grid's v (the velocity through the grid). Each cell's
  // corner forces first, then each node sums its cells in a fixed order: the same bits for any
  // thread count.
  void compute(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials,
               bool parallel) {
    const std::ptrdiff_t n = std::ptrdiff_t(g.size());
    force.assign(g.size(), Vec<T, D>::Zero());
    corner_.assign(g.size() * P, Vec<T, D>::Zero());
    std::array<std::size_t, P> offset{};
    for (int k = 0; k < P; ++k) offset[std::size_t(k)] = corner_node(g, 0, k);
#pragma omp parallel if (parallel)
    {
#pragma omp for schedule(static)
      for (std::ptrdiff_t b = 0; b < n; ++b) cell(g, materials, std::size_t(b), offset);
#pragma omp for schedule(static)
      for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
        const std::size_t i = std::size_t(ii);
        const auto c = g.coords(i);
        for (int k = 0; k < P; ++k) {  // node i is corner k of the cell based at i − offset_k
          bool inside = true;
          for (int a = 0; a < D; ++a)
            if ((k & (1 << a)) && c[a] == 0) inside = false;
          if (inside) force[i] += corner_[(i - offset[std::size_t(k)]) * P + std::size_t(k)];
        }
      }
    }
  }
  std::vector<Vec<T, D>> force;

 private:
  void cell(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials,
            std::size_t base, const std::array<std::size_t, P>& offset) {
    if (!is_cell_base(g, base)) return;
    const int m = cell_material(g, base);
    if (m < 0) return;
    const T eta = materials[std::size_t(m)].viscosity;
    if (!(eta > T(0))) return;
    const T inv_dx = T(1) / g.dx;
    T volume_scale = quad_.weight;
    for (int a = 0; a < D; ++a) volume_scale *= g.dx;
    Vec<T, D>* corner = &corner_[base * P];
    for (int q = 0; q < P; ++q) {
      Mat<T, D> G = Mat<T, D>::Zero();  // ∇_y v
      T fill = T(0);
      for (int k = 0; k < P; ++k) {
        const std::size_t i = base + offset[std::size_t(k)];
        G += g.v[i] * quad_.dN[std::size_t(q)][std::size_t(k)].transpose();
        fill += quad_.N[std::size_t(q)][std::size_t(k)] * g.fill[i];
      }
      if (!(fill > T(0))) continue;
      G *= inv_dx;
      const Mat<T, D> tau = (volume_scale * fill * eta) * (G + G.transpose());
      for (int k = 0; k < P; ++k)
        corner[k] -= tau * (quad_.dN[std::size_t(q)][std::size_t(k)] * inv_dx);
    }
  }
  CellQuadrature<T, D> quad_;
  std::vector<Vec<T, D>> corner_;  // per cell base node: [corner]
};

}  // namespace apiclab::eol
