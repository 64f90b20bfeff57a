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
#include <algorithm>
#include <array>
#include <type_traits>
#include <vector>

#include "sim/eol/frame.hpp"
#include "sim/eol/grid/cell_points.hpp"
#include "sim/eol/grid/eulerian_grid.hpp"
#include "sim/eol/plastic_samples.hpp"
#include "sim/materials.hpp"

namespace apiclab::eol {

template <class T>
struct ElasticMaterial {
  MaterialModel model;
  Lame<T> lame;
  T viscosity = T(0);        // Kelvin–Voigt η (viscosity.hpp)
  PlasticParams<T> plastic;  // the plastic model's yield stress and flow rate (eq 37)
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

// Per cell, the force density τ = V₀ P Fᵀ at its Gauss points (zero where the cell is empty or
// inverted) and the cell's share of each corner's force, f_k = −Σ_q τ_q ∇_y N_k(ξ_q), added to
// its corner nodes right away. Cells go layer by layer along the last axis, the even layers
// first, then the odd ones (two layers of one parity share no node), each layer on one thread,
// so threads never write the same node and every node sums its cells in one order: the same
// result for any thread count.
// Forces in frame axes. The points of a cell are SIMD lanes (cell_points.hpp); for the
// neo-Hookean model the Kirchhoff stress is written directly, P Fᵀ = μ F Fᵀ + (λ log J − μ) I
// (F⁻ᵀ Fᵀ = I), with F = Δx adj(A)/det A and J = Δx^d/det A, so no inverse or cofactor of F is
// formed.
template <class T, int D>
class ElasticForces {
  static constexpr int P = 1 << D;  // Gauss points = corners per cell

 public:
  std::size_t bytes() const {
    return held_bytes(cells_) + held_bytes(layer_start_) + held_bytes(layer_active_) +
           held_bytes(layer_order_[0]) + held_bytes(layer_order_[1]) + held_bytes(corner_mass_) +
           held_bytes(cell_energy_) + held_bytes(mass_active_) + held_bytes(kept_);
  }
  // The lumped node masses of the same quadrature (eq 6 with J̄ = det ∇X): each Gauss point's
  // ρ₀ V₀ shared by N_k. Mass and force come from the same points, so a node at the surface
  // gets as little force as it has mass (a node mass from its own fill alone would leave
  // nearly empty nodes with large accelerations and break the explicit step).
  // keep (optional, may alias mass: read before mass is written): cells whose corners all have
  // keep > 0 keep their corner masses from the previous call, as their X and H are unchanged
  // (the second pass of a step, after extrapolation wrote only the empty nodes).
  void lumped_mass(const EulerianGrid<T, D>& g, const std::vector<T>& density, std::vector<T>& mass,
                   bool parallel, const std::vector<T>* keep = nullptr) {
    if (ensure_cells(g)) keep = nullptr;
    const std::ptrdiff_t ncell = std::ptrdiff_t(cells_.size());
#pragma omp parallel for if (parallel)
    for (std::ptrdiff_t c = 0; c < ncell; ++c) {
      bool kept = keep != nullptr;
      for (int k = 0; k < P && kept; ++k)
        kept = (*keep)[cells_[std::size_t(c)] + offset_[std::size_t(k)]] > T(0);
      kept_[std::size_t(c)] = kept;
    }
    auto zero = [&](std::size_t i) { mass[i] = T(0); };
    auto no_finish = [](std::size_t) {};
    for_each_cell_by_layer(g.size(), parallel, zero, no_finish, [&](std::size_t c) {
      const std::size_t base = cells_[c];
      T* corner = &corner_mass_[c * P];  // Σ_q N_k(ξ_q) m_q, lanes k
      if (!kept_[c]) {
        const int m = material_of(g, base);
        mass_active_[c] = m >= 0;
        if (m < 0) return false;  // empty cell: no corner masses
        CellPoints<T, D> pts;
        evaluate(g, base, pts);
        const T rho_w = density[std::size_t(m)] * quad_.weight;
        alignas(64) T point_mass[P];
#pragma omp simd
        for (int q = 0; q < P; ++q)
          point_mass[q] =
              pts.fill[q] > T(0) && pts.det[q] > T(0) ? rho_w * pts.det[q] * pts.fill[q] : T(0);
#pragma omp simd
        for (int k = 0; k < P; ++k) corner[k] = T(0);
        for (int q = 0; q < P; ++q) {
          const T mq = point_mass[q];
#pragma omp simd
          for (int k = 0; k < P; ++k) corner[k] += quad_.N_lanes_k[q][k] * mq;
        }
      } else if (!mass_active_[c]) {
        return false;
      }
      for (int k = 0; k < P; ++k) mass[base + offset_[std::size_t(k)]] += corner[k];
      return true;
    });
  }

  // finish(i) runs for every node once its elastic force is complete, in the same parallel
  // region (the caller's per-node forces: gravity, f_qvv, the frame rotation). plastic: the
  // object's F_p⁻¹ samples, for the cells of a plastic material (eq 34).
  template <class Finish>
  void compute(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials,
               std::vector<Vec<T, D>>& force, bool parallel, Finish&& finish,
               const PlasticSamples<T, D>* plastic = nullptr) {
    ensure_cells(g);
    auto zero = [&](std::size_t i) { force[i].setZero(); };
    for_each_cell_by_layer(g.size(), parallel, zero, finish, [&](std::size_t c) {
      const std::size_t base = cells_[c];
      const int m = material_of(g, base);
      cell_energy_[c] = 0;
      if (m < 0) return false;
      CellPoints<T, D> pts;
      evaluate(g, base, pts);
      alignas(64) T tau[D][D][P], vpsi[P], f[D][P];
      const ElasticMaterial<T>& mat = materials[std::size_t(m)];
      if (mat.model == MaterialModel::neo_hookean)
        neo_hookean_tau(g.dx, mat.lame, pts, tau, vpsi);
      else if (plastic != nullptr && mat.model == MaterialModel::plastic)
        plastic_tau(g, base, mat, *plastic, pts, tau, vpsi);
      else
        general_tau(g.dx, mat, pts, tau, vpsi);
      const T inv_dx = T(1) / g.dx;
      // f_k = −Σ_q τ_q ∇_y N_k(ξ_q), lanes k, the D components' sums in registers side by
      // side: D independent chains of FMAs (summed through f[a][k] in memory, every FMA waited
      // for the last one's store).
#pragma omp simd
      for (int k = 0; k < P; ++k) {
        T sum[D] = {};
        for (int q = 0; q < P; ++q)
          for (int b = 0; b < D; ++b) {
            const T dn = quad_.dN_lanes_k[q][b][k];
            for (int a = 0; a < D; ++a) sum[a] -= tau[a][b][q] * dn;
          }
        for (int a = 0; a < D; ++a) f[a][k] = sum[a] * inv_dx;
      }
      for (int k = 0; k < P; ++k) {
        Vec<T, D>& node = force[base + offset_[std::size_t(k)]];
        for (int a = 0; a < D; ++a) node[a] += f[a][k];
      }
      // Ψ at the same points for the diagnostics: elastic_energy_moved's sum, F there being
      // (∂y/∂ξ) A⁻¹ with ∂y/∂ξ = Δx I up to round-off.
      double energy = 0;
      for (int q = 0; q < P; ++q) energy += double(vpsi[q]);
      cell_energy_[c] = energy;
      return true;
    });
  }
  void compute(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials,
               std::vector<Vec<T, D>>& force, bool parallel) {
    compute(g, materials, force, parallel, [](std::size_t) {});
  }
  // E = Σ V₀ Ψ(F) of the last compute(), summed in the cells' order (index order; the same
  // for any thread count).
  double energy() const {
    double e = 0;
    for (double x : cell_energy_) e += x;
    return e;
  }

 private:
  // The cell's corners into lanes, then A, det A and H at its points.
  void evaluate(const EulerianGrid<T, D>& g, std::size_t base, CellPoints<T, D>& pts) const {
    alignas(64) T X[D][P], H[P];
    for (int k = 0; k < P; ++k) {
      const std::size_t i = base + offset_[std::size_t(k)];
      for (int a = 0; a < D; ++a) X[a][k] = g.X[i][a];
      H[k] = g.fill[i];
    }
    pts.evaluate(quad_, X, H);
  }
  // τ = V₀ (μ (F Fᵀ − I) + λ log J I) and V₀ Ψ = V₀ (½ μ (tr F Fᵀ − d) − μ log J + ½ λ log² J)
  // per lane; V₀ = 0 (and det A taken as 1, to keep the lane finite) where the point is empty
  // or inverted.
  void neo_hookean_tau(T dx, const Lame<T>& l, const CellPoints<T, D>& pts, T (&tau)[D][D][P],
                       T (&vpsi)[P]) const {
    alignas(64) T volume[P], J[P], logJ[P], b[D][D][P];
    const T dx_d = D == 2 ? dx * dx : dx * dx * dx;
    // F and b = F Fᵀ as named lane values in one vector loop (it ran scalar, point by point;
    // the vector code rounds differently: EolForces.LanesMatchThePerPointFormula bounds it).
#pragma omp simd
    for (int q = 0; q < P; ++q)
      volume[q] =
          pts.fill[q] > T(0) && pts.det[q] > T(0) ? pts.det[q] * quad_.weight * pts.fill[q] : T(0);
      // (GCC 12 leaves the loop above scalar, and with it any loop that tests fill and det: so
      // the one below tests the volume.)
#pragma omp simd
    for (int q = 0; q < P; ++q) {
      const T det = volume[q] > T(0) ? pts.det[q] : T(1);
      J[q] = dx_d / det;
      const T s = dx / det;  // F = s adj(A)
      if constexpr (D == 2) {
        const T f00 = s * pts.A[1][1][q], f01 = -s * pts.A[0][1][q];
        const T f10 = -s * pts.A[1][0][q], f11 = s * pts.A[0][0][q];
        b[0][0][q] = f00 * f00 + f01 * f01;
        b[0][1][q] = b[1][0][q] = f00 * f10 + f01 * f11;
        b[1][1][q] = f10 * f10 + f11 * f11;
      } else {
        const auto& A = pts.A;
        const T f00 = s * (A[1][1][q] * A[2][2][q] - A[1][2][q] * A[2][1][q]);
        const T f01 = s * (A[0][2][q] * A[2][1][q] - A[0][1][q] * A[2][2][q]);
        const T f02 = s * (A[0][1][q] * A[1][2][q] - A[0][2][q] * A[1][1][q]);
        const T f10 = s * (A[1][2][q] * A[2][0][q] - A[1][0][q] * A[2][2][q]);
        const T f11 = s * (A[0][0][q] * A[2][2][q] - A[0][2][q] * A[2][0][q]);
        const T f12 = s * (A[0][2][q] * A[1][0][q] - A[0][0][q] * A[1][2][q]);
        const T f20 = s * (A[1][0][q] * A[2][1][q] - A[1][1][q] * A[2][0][q]);
        const T f21 = s * (A[0][1][q] * A[2][0][q] - A[0][0][q] * A[2][1][q]);
        const T f22 = s * (A[0][0][q] * A[1][1][q] - A[0][1][q] * A[1][0][q]);
        b[0][0][q] = f00 * f00 + f01 * f01 + f02 * f02;
        b[0][1][q] = b[1][0][q] = f00 * f10 + f01 * f11 + f02 * f12;
        b[0][2][q] = b[2][0][q] = f00 * f20 + f01 * f21 + f02 * f22;
        b[1][1][q] = f10 * f10 + f11 * f11 + f12 * f12;
        b[1][2][q] = b[2][1][q] = f10 * f20 + f11 * f21 + f12 * f22;
        b[2][2][q] = f20 * f20 + f21 * f21 + f22 * f22;
      }
    }
#pragma omp simd
    for (int q = 0; q < P; ++q) logJ[q] = std::log(J[q]);
#pragma omp simd
    for (int q = 0; q < P; ++q) {
      const T pressure = l.lambda * logJ[q] - l.mu;
      T trace = T(0);
      for (int r = 0; r < D; ++r) {
        trace += b[r][r][q];
        for (int c = 0; c < D; ++c)
          tau[r][c][q] = volume[q] * (l.mu * b[r][c][q] + (r == c ? pressure : T(0)));
      }
      vpsi[q] = volume[q] * (T(0.5) * l.mu * (trace - T(D)) - l.mu * logJ[q] +
                             T(0.5) * l.lambda * logJ[q] * logJ[q]);
    }
  }
  // Any model, one point at a time: F = Δx A⁻¹, P and Ψ from materials.hpp, τ = V₀ P Fᵀ.
  void general_tau(T dx, const ElasticMaterial<T>& mat, const CellPoints<T, D>& pts,
                   T (&tau)[D][D][P], T (&vpsi)[P]) const {
    tau_of(
        mat, pts, [&](int q) -> Mat<T, D> { return dx * pts.matrix(q).inverse(); }, tau, vpsi);
  }
  // Eq 34: at each point F_e = F F_p⁻¹(X_q), F_p⁻¹ looked up at the point's material coordinate;
  // τ = V₀ P(F_e) F_eᵀ, the gradient of V₀ Ψ(F F_p⁻¹) in y (F_p held, as X is).
  void plastic_tau(const EulerianGrid<T, D>& g, std::size_t base, const ElasticMaterial<T>& mat,
                   const PlasticSamples<T, D>& plastic, const CellPoints<T, D>& pts,
                   T (&tau)[D][D][P], T (&vpsi)[P]) const {
    const auto Fe = [&](int q) -> Mat<T, D> {
      Vec<T, D> X = Vec<T, D>::Zero();
      for (int k = 0; k < P; ++k) X += quad_.N_lanes_k[q][k] * g.X[base + offset_[std::size_t(k)]];
      return g.dx * pts.matrix(q).inverse() * plastic.at(X);
    };
    tau_of(mat, pts, Fe, tau, vpsi);
  }
  // τ = V₀ P(F) Fᵀ and V₀ Ψ(F) at each filled point, F = F_of(q) (the elastic part of F).
  template <class FOf>
  void tau_of(const ElasticMaterial<T>& mat, const CellPoints<T, D>& pts, const FOf& F_of,
              T (&tau)[D][D][P], T (&vpsi)[P]) const {
    for (int q = 0; q < P; ++q) {
      Mat<T, D> t = Mat<T, D>::Zero();
      vpsi[q] = T(0);
      if (pts.fill[q] > T(0) && pts.det[q] > T(0)) {
        const Mat<T, D> F = F_of(q);
        Mat<T, D> Pk;
        T psi;
        stress_and_energy<T, D>(mat, F, Pk, psi);
        const T volume = pts.det[q] * quad_.weight * pts.fill[q];
        t = volume * Pk * F.transpose();
        vpsi[q] = volume * psi;
      }
      for (int r = 0; r < D; ++r)
        for (int c = 0; c < D; ++c) tau[r][c][q] = t(r, c);
    }
  }
  // cell_material with the corner offsets.
  int material_of(const EulerianGrid<T, D>& g, std::size_t base) const {
    for (int k = 0; k < P; ++k) {
      const int m = g.material[base + offset_[std::size_t(k)]];
      if (m >= 0) return m;
    }
    return -1;
  }
  // Whether the cell list was (re)built: every cell's lowest node in index order, so each layer
  // of cells (one coordinate of the last axis) is a contiguous range.
  bool ensure_cells(const EulerianGrid<T, D>& g) {
    if (!cells_.empty() && grid_nodes_ == g.size()) return false;
    cells_.clear();
    layer_start_.clear();
    for (std::size_t i = 0; i < g.size(); ++i) {
      if (!is_cell_base(g, i)) continue;
      if (g.coords(i)[D - 1] == int(layer_start_.size())) layer_start_.push_back(cells_.size());
      cells_.push_back(i);
    }
    layer_start_.push_back(cells_.size());
    const std::size_t layers = layer_start_.size() - 1;
    layer_active_.assign(layers, 0);
    for (auto& order : layer_order_) order.clear();
    for (std::size_t z = 0; z < layers; ++z) layer_order_[z % 2].push_back(int(z));
    grid_nodes_ = g.size();
    for (int k = 0; k < P; ++k) offset_[std::size_t(k)] = corner_node(g, 0, k);
    corner_mass_.assign(cells_.size() * P, T(0));
    cell_energy_.assign(cells_.size(), 0.0);
    mass_active_.assign(cells_.size(), 0);
    kept_.assign(cells_.size(), 0);
    return true;
  }
  // zero(i) for every node, then cell(c) for every cell (true when it holds material): the even
  // layers, then (after the `omp for` barrier) the odd ones, then finish(i) for every node, all
  // in one parallel region. Two layers of one parity share no node, so threads never write the
  // same node; each layer runs on one thread in index order, so every node sums its cells in
  // the same order for any thread count, whichever thread takes a layer. So layers are handed
  // out dynamically, heaviest first (by the cells with material each held last pass): a thread
  // slowed by other work on the machine leaves the rest to the others, and the big middle
  // layers do not end a colour on one thread (docs/eol.md#what-makes-the-step-fast).
  template <class Zero, class Finish, class Cell>
  void for_each_cell_by_layer(std::size_t nodes, bool parallel, Zero&& zero, Finish&& finish,
                              Cell&& cell) {
    const std::ptrdiff_t n = std::ptrdiff_t(nodes);
#pragma omp parallel if (parallel)
    {
#pragma omp for schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) zero(std::size_t(i));
      for (int colour = 0; colour < 2; ++colour) {
        const std::vector<int>& order = layer_order_[std::size_t(colour)];
        const std::ptrdiff_t count = std::ptrdiff_t(order.size());
#pragma omp for schedule(dynamic, 1)
        for (std::ptrdiff_t j = 0; j < count; ++j) {
          const std::size_t layer = std::size_t(order[std::size_t(j)]);
          std::size_t active = 0;
          for (std::size_t c = layer_start_[layer]; c < layer_start_[layer + 1]; ++c)
            active += cell(c) ? 1 : 0;
          layer_active_[layer] = active;
        }
      }
#pragma omp for schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) finish(std::size_t(i));
    }
    for (auto& order : layer_order_)  // heaviest first, ties in index order (sort: no buffer)
      std::sort(order.begin(), order.end(), [&](int a, int b) {
        const std::size_t wa = layer_active_[std::size_t(a)], wb = layer_active_[std::size_t(b)];
        return wa != wb ? wa > wb : a < b;
      });
  }

  CellQuadrature<T, D> quad_;
  std::array<std::size_t, P> offset_{};    // node index of corner k minus the base's
  std::vector<std::size_t> cells_;         // lowest node of each cell, in index order
  std::vector<std::size_t> layer_start_;   // layer z: cells_[layer_start_[z], layer_start_[z + 1])
  std::vector<std::size_t> layer_active_;  // per layer: cells with material in the last pass
  std::array<std::vector<int>, 2> layer_order_;  // even, odd layers: the order they are handed out
  std::vector<T> corner_mass_;                   // per cell: [corner]
  std::vector<double> cell_energy_;
  std::vector<char> mass_active_;  // per cell: holds material (as of its last mass evaluation)
  std::vector<char> kept_;         // per cell: keeps its corner masses in this lumped_mass
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
