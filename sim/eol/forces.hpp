// Forces on the nodes of an object's Eulerian grid (Fan et al. 2013, eq 12): elasticity f_e from
// F = (∇_y X)⁻¹ through the shared materials, gravity f_b, and the quadratic-velocity forces
// f_qvv of the moving frame (centrifugal and Coriolis).
//
// Elasticity is integrated with 2^d Gauss points per cell of the multilinear grid (one point
// would leave hourglass modes of X without force). At a point, A = ∂X/∂ξ (ξ the cell's unit
// coordinates), the material volume is V₀ = det A w H (H the interpolated rest-shape fill), and
// with the grid undeformed (∂y/∂ξ = Δx I) F = Δx A⁻¹. The force is f_k = −Σ V₀ P Fᵀ ∇_y N_k,
// the exact gradient of E = Σ V₀ Ψ(F) with respect to the node positions (tested against
// finite differences of elastic_energy_moved).
#pragma once
#include <array>
#include <type_traits>
#include <vector>

#include "sim/eol/eulerian_grid.hpp"
#include "sim/eol/frame.hpp"
#include "sim/materials.hpp"

namespace apiclab::eol {

template <class T>
struct ElasticMaterial {
  MaterialModel model;
  Lame<T> lame;
};

// The 2^d Gauss points of the unit cell: ξ_a = ½ ± ½/√3, weight 2^-d.
template <class T, int D>
struct CellQuadrature {
  static constexpr int points = 1 << D, corners = 1 << D;
  std::array<std::array<T, corners>, points> N;           // N_k(ξ_q)
  std::array<std::array<Vec<T, D>, corners>, points> dN;  // ∇_ξ N_k(ξ_q)
  T weight = T(1) / T(points);
  CellQuadrature() {
    const T g = T(0.5) / std::sqrt(T(3));
    for (int q = 0; q < points; ++q)
      for (int k = 0; k < corners; ++k) {
        T value = T(1);
        Vec<T, D> grad = Vec<T, D>::Ones();
        for (int a = 0; a < D; ++a) {
          const T xi = q & (1 << a) ? T(0.5) + g : T(0.5) - g;
          const bool up = k & (1 << a);
          const T factor = up ? xi : T(1) - xi, slope = up ? T(1) : T(-1);
          value *= factor;
          for (int b = 0; b < D; ++b) grad[b] *= b == a ? slope : factor;
        }
        N[std::size_t(q)][std::size_t(k)] = value;
        dN[std::size_t(q)][std::size_t(k)] = grad;
      }
  }
};

// Node index of corner k of the cell whose lowest node is `base`.
template <class T, int D>
std::size_t corner_node(const EulerianGrid<T, D>& g, std::size_t base, int k) {
  std::size_t i = base;
  for (int a = 0; a < D; ++a)
    if (k & (1 << a)) i += g.stride(a);
  return i;
}

// The material of a cell: that of its first corner with one (grids of one object have one).
template <class T, int D>
int cell_material(const EulerianGrid<T, D>& g, std::size_t base) {
  for (int k = 0; k < (1 << D); ++k) {
    const int m = g.material[corner_node(g, base, k)];
    if (m >= 0) return m;
  }
  return -1;
}

// Whether node i is the lowest node of a cell.
template <class T, int D>
bool is_cell_base(const EulerianGrid<T, D>& g, std::size_t i) {
  const auto c = g.coords(i);
  for (int a = 0; a < D; ++a)
    if (c[a] + 1 >= g.n[a]) return false;
  return true;
}

// E = Σ_cells Σ_q V₀ Ψ(F) with the nodes moved to y + dy (dy empty: the grid as it is), X and H
// held: F = (∂y/∂ξ)(∂X/∂ξ)⁻¹. The reference the forces are the gradient of.
template <class T, int D>
double elastic_energy_moved(const EulerianGrid<T, D>& g,
                            const std::vector<ElasticMaterial<T>>& materials,
                            const std::vector<Vec<T, D>>& dy = {}) {
  static const CellQuadrature<T, D> quad;
  double energy = 0;
  for (std::size_t base = 0; base < g.size(); ++base) {
    if (!is_cell_base(g, base)) continue;
    const int m = cell_material(g, base);
    if (m < 0) continue;
    for (int q = 0; q < quad.points; ++q) {
      Mat<T, D> A = Mat<T, D>::Zero(), Y = Mat<T, D>::Zero();
      T fill = T(0);
      for (int k = 0; k < quad.corners; ++k) {
        const std::size_t i = corner_node(g, base, k);
        const Vec<T, D>& dn = quad.dN[std::size_t(q)][std::size_t(k)];
        A += g.X[i] * dn.transpose();
        Vec<T, D> y = g.y(i);
        if (!dy.empty()) y += dy[i];
        Y += y * dn.transpose();
        fill += quad.N[std::size_t(q)][std::size_t(k)] * g.fill[i];
      }
      const T detA = A.determinant();
      if (!(fill > T(0)) || !(detA > T(0))) continue;
      const Mat<T, D> F = Y * A.inverse();
      energy += double(detA * quad.weight * fill) *
                double(energy_density<T, D>(materials[std::size_t(m)].model, F,
                                            materials[std::size_t(m)].lame));
    }
  }
  return energy;
}

// P(F) and Ψ(F) at once; the neo-Hookean model shares J and log J (materials.hpp's expressions).
template <class T, int D>
void stress_and_energy(const ElasticMaterial<T>& mat, const Mat<T, D>& F, Mat<T, D>& P, T& psi) {
  if (mat.model == MaterialModel::neo_hookean) {
    const T J = F.determinant();
    if (J > T(0)) {
      const Lame<T>& l = mat.lame;
      const T logJ = std::log(J);
      P = l.mu * F + ((l.lambda * logJ - l.mu) / J) * cofactor<T, D>(F);
      psi =
          T(0.5) * l.mu * (F.squaredNorm() - T(D)) - l.mu * logJ + T(0.5) * l.lambda * logJ * logJ;
      return;
    }
  }
  P = first_piola<T, D>(mat.model, F, mat.lame);
  psi = energy_density<T, D>(mat.model, F, mat.lame);
}

// Per cell and Gauss point, the force density V₀ P Fᵀ (zero where the cell is empty or
// inverted), then f_k = −Σ V₀ P Fᵀ ∇_y N_k gathered per node. Forces in frame axes.
template <class T, int D>
class ElasticForces {
 public:
  std::size_t bytes() const {
    return held_bytes(cells_) + held_bytes(cell_of_) + held_bytes(tau_) + held_bytes(point_mass_) +
           held_bytes(cell_energy_) + held_bytes(mass_active_) + held_bytes(force_active_);
  }
  // The lumped node masses of the same quadrature (eq 6 with J̄ = det ∇X): each Gauss point's
  // ρ₀ V₀ shared by N_k. Mass and force come from the same points, so a node at the surface
  // gets as little force as it has mass (a node mass from its own fill alone would leave
  // nearly empty nodes with large accelerations and break the explicit step).
  // keep (optional, may alias mass: read before mass is written): cells whose corners all have
  // keep > 0 keep their point masses from the previous call, as their X and H are unchanged
  // (the second pass of a step, after extrapolation wrote only the empty nodes).
  void lumped_mass(const EulerianGrid<T, D>& g, const std::vector<T>& density, std::vector<T>& mass,
                   bool parallel, const std::vector<T>* keep = nullptr) {
    if (ensure_cells(g)) keep = nullptr;
    const std::ptrdiff_t ncell = std::ptrdiff_t(cells_.size());
#pragma omp parallel for if (parallel)
    for (std::ptrdiff_t c = 0; c < ncell; ++c) {
      const std::size_t base = cells_[std::size_t(c)];
      if (keep) {
        bool kept = true;
        for (int k = 0; k < quad_.corners && kept; ++k)
          kept = (*keep)[base + offset_[std::size_t(k)]] > T(0);
        if (kept) continue;
      }
      const int m = material_of(g, base);
      mass_active_[std::size_t(c)] = m >= 0;
      if (m < 0) continue;  // empty cell: skipped by the gather, no point masses written
      Corners corners;
      load(g, base, corners);
      for (int q = 0; q < quad_.points; ++q) {
        Mat<T, D> A;
        T fill;
        at_point(corners, q, A, fill);
        const T detA = A.determinant();
        point_mass_[std::size_t(c) * quad_.points + std::size_t(q)] =
            fill > T(0) && detA > T(0) ? density[std::size_t(m)] * detA * quad_.weight * fill
                                       : T(0);
      }
    }
    gather(
        g, mass_active_,
        [&](std::size_t cell, int k) {
          T sum = T(0);
          for (int q = 0; q < quad_.points; ++q)
            sum += quad_.N[std::size_t(q)][std::size_t(k)] *
                   point_mass_[cell * quad_.points + std::size_t(q)];
          return sum;
        },
        mass, parallel);
  }

  void compute(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials,
               std::vector<Vec<T, D>>& force, bool parallel) {
    ensure_cells(g);
    const std::ptrdiff_t ncell = std::ptrdiff_t(cells_.size());
    const T inv_dx = T(1) / g.dx;
#pragma omp parallel for if (parallel)
    for (std::ptrdiff_t c = 0; c < ncell; ++c) {
      const std::size_t base = cells_[std::size_t(c)];
      const int m = material_of(g, base);
      force_active_[std::size_t(c)] = m >= 0;
      cell_energy_[std::size_t(c)] = 0;
      if (m < 0) continue;
      Corners corners;
      load(g, base, corners);
      double energy = 0;
      for (int q = 0; q < quad_.points; ++q) {
        Mat<T, D>& tau = tau_[std::size_t(c) * quad_.points + std::size_t(q)];
        tau.setZero();
        Mat<T, D> A;
        T fill;
        at_point(corners, q, A, fill);
        const T detA = A.determinant();
        if (!(fill > T(0)) || !(detA > T(0))) continue;
        const Mat<T, D> F = g.dx * A.inverse();
        Mat<T, D> P;
        T psi;
        stress_and_energy<T, D>(materials[std::size_t(m)], F, P, psi);
        tau = (detA * quad_.weight * fill) * P * F.transpose();
        // Ψ at the same point for the diagnostics: elastic_energy_moved's sum, F there being
        // (∂y/∂ξ) A⁻¹ with ∂y/∂ξ = Δx I up to round-off.
        energy += double(detA * quad_.weight * fill) * double(psi);
      }
      cell_energy_[std::size_t(c)] = energy;
    }
    gather(
        g, force_active_,
        [&](std::size_t cell, int k) {
          Vec<T, D> f = Vec<T, D>::Zero();
          for (int q = 0; q < quad_.points; ++q)
            f -= tau_[cell * quad_.points + std::size_t(q)] *
                 (quad_.dN[std::size_t(q)][std::size_t(k)] * inv_dx);
          return f;
        },
        force, parallel);
  }
  // E = Σ V₀ Ψ(F) of the last compute(), summed in cell order (the same for any thread count).
  double energy() const {
    double e = 0;
    for (double x : cell_energy_) e += x;
    return e;
  }

 private:
  struct Corners {
    std::array<Vec<T, D>, 1 << D> X;
    std::array<T, 1 << D> fill;
  };
  void load(const EulerianGrid<T, D>& g, std::size_t base, Corners& out) const {
    for (int k = 0; k < quad_.corners; ++k) {
      out.X[std::size_t(k)] = g.X[base + offset_[std::size_t(k)]];
      out.fill[std::size_t(k)] = g.fill[base + offset_[std::size_t(k)]];
    }
  }
  // A = ∂X/∂ξ and the interpolated fill at Gauss point q (summed in corner order).
  void at_point(const Corners& cr, int q, Mat<T, D>& A, T& fill) const {
    A.setZero();
    fill = T(0);
    for (int k = 0; k < quad_.corners; ++k) {
      A += cr.X[std::size_t(k)] * quad_.dN[std::size_t(q)][std::size_t(k)].transpose();
      fill += quad_.N[std::size_t(q)][std::size_t(k)] * cr.fill[std::size_t(k)];
    }
  }
  // cell_material with the corner offsets.
  int material_of(const EulerianGrid<T, D>& g, std::size_t base) const {
    for (int k = 0; k < quad_.corners; ++k) {
      const int m = g.material[base + offset_[std::size_t(k)]];
      if (m >= 0) return m;
    }
    return -1;
  }
  // Whether the cell list was (re)built.
  bool ensure_cells(const EulerianGrid<T, D>& g) {
    if (!cells_.empty() && grid_nodes_ == g.size()) return false;
    cells_.clear();
    for (std::size_t i = 0; i < g.size(); ++i)
      if (is_cell_base(g, i)) cells_.push_back(i);
    grid_nodes_ = g.size();
    for (int k = 0; k < quad_.corners; ++k) offset_[std::size_t(k)] = corner_node(g, 0, k);
    tau_.assign(cells_.size() * quad_.points, Mat<T, D>::Zero());
    point_mass_.assign(cells_.size() * quad_.points, T(0));
    cell_energy_.assign(cells_.size(), 0.0);
    mass_active_.assign(cells_.size(), 0);
    force_active_.assign(cells_.size(), 0);
    cell_of_.assign(g.size(), -1);
    for (std::size_t c = 0; c < cells_.size(); ++c) cell_of_[cells_[c]] = std::ptrdiff_t(c);
    return true;
  }
  // out[i] = Σ over the active cells around node i of part(cell, k), node i being the cell's
  // corner k.
  template <class V, class Part>
  void gather(const EulerianGrid<T, D>& g, const std::vector<char>& active, Part&& part,
              std::vector<V>& out, bool parallel) {
    const std::ptrdiff_t nnode = std::ptrdiff_t(g.size());
#pragma omp parallel for if (parallel)
    for (std::ptrdiff_t ii = 0; ii < nnode; ++ii) {
      const std::size_t i = std::size_t(ii);
      const auto c = g.coords(i);
      V sum;
      if constexpr (std::is_arithmetic_v<V>)
        sum = V(0);
      else
        sum.setZero();
      for (int k = 0; k < quad_.corners; ++k) {
        bool valid = true;
        std::size_t base = i;
        for (int a = 0; a < D; ++a)
          if (k & (1 << a)) {
            if (c[a] == 0)
              valid = false;
            else
              base -= g.stride(a);
          }
        if (!valid || cell_of_[base] < 0 || !active[std::size_t(cell_of_[base])]) continue;
        sum += part(std::size_t(cell_of_[base]), k);
      }
      out[i] = sum;
    }
  }

  CellQuadrature<T, D> quad_;
  std::array<std::size_t, 1 << D> offset_{};  // node index of corner k minus the base's
  std::vector<std::size_t> cells_;
  std::vector<std::ptrdiff_t> cell_of_;
  std::vector<Mat<T, D>> tau_;
  std::vector<T> point_mass_;
  std::vector<double> cell_energy_;
  std::vector<char> mass_active_, force_active_;  // per cell: holds material
  std::size_t grid_nodes_ = 0;
};

// f_qvv of eq 12 for a node of mass m at world offset r with Eulerian velocity w = R v (world
// axes): the centrifugal −m ω × (ω × r) and Coriolis −2m ω × w forces. Advancing the frame
// carries the rigid velocity ν + ω × r of every node with it; these forces take that back out of
// the Eulerian part, so the material's spatial velocity is unchanged by the frame's motion alone.
template <class T, int D>
Vec<T, D> quadratic_velocity_force(T m, const Spin<T, D>& omega, const Vec<T, D>& r,
                                   const Vec<T, D>& w) {
  return -m *
         (spin_cross<T, D>(omega, spin_cross<T, D>(omega, r)) + T(2) * spin_cross<T, D>(omega, w));
}

}  // namespace apiclab::eol
