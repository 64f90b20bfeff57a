// F_p stored in the material domain (Fan et al. 2013, Sec 3.7): F_p⁻¹ on a lattice of material
// samples Z, spacing the object's Δx, over its plastic rest shapes. Eq 34 reads it through X
// (multilinear in Z, `at`); eq 35 updates it at the samples, each placed in the intermediate
// domain by Algorithm 2's Newton iteration from its last placement (the paper's interpolated
// map from material to space). Nothing advects it, so it cannot smear.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "sim/eol/grid/eulerian_grid.hpp"
#include "sim/eol/surface/surface_placement.hpp"
#include "sim/plasticity.hpp"

namespace apiclab::eol {

template <class T, int D>
struct PlasticSamples {
  Vec<T, D> origin = Vec<T, D>::Zero();  // Z of sample 0
  T h = T(1);                            // spacing
  std::array<int, D> n{};                // samples per axis
  std::vector<Mat<T, D>> fp_inv;         // F_p⁻¹ per sample
  std::vector<std::int32_t> material;    // plastic material (-1: none within a cell; never updated)
  std::vector<char> identity;            // F_p⁻¹ still the identity bit for bit
  std::vector<Vec<T, D>> y;              // last placement in the intermediate domain
  // The last update: samples that flowed, and the largest |det ΔF_p⁻¹ − 1| among them.
  std::size_t flowed = 0;
  double det_error = 0;

  bool empty() const { return fp_inv.empty(); }
  std::size_t size() const { return fp_inv.size(); }
  std::size_t bytes() const {
    return held_bytes(fp_inv) + held_bytes(material) + held_bytes(identity) + held_bytes(y);
  }
  std::size_t index(const std::array<int, D>& c) const {
    std::size_t i = std::size_t(c[D - 1]);
    for (int a = D - 2; a >= 0; --a) i = i * std::size_t(n[a]) + std::size_t(c[a]);
    return i;
  }
  Vec<T, D> position(std::size_t i) const {
    Vec<T, D> z = origin;
    for (int a = 0; a < D; ++a) {
      z[a] += h * T(i % std::size_t(n[a]));
      i /= std::size_t(n[a]);
    }
    return z;
  }

  // F_p⁻¹ at material point Z: multilinear over the lattice cell holding it; the identity
  // exactly outside the lattice or where the cell's samples all are.
  Mat<T, D> at(const Vec<T, D>& Z) const {
    std::array<int, D> c;
    std::array<T, D> t;
    for (int a = 0; a < D; ++a) {
      const T s = (Z[a] - origin[a]) / h;
      if (!(s >= T(0)) || !(s <= T(n[a] - 1))) return Mat<T, D>::Identity();
      c[a] = std::min(int(s), n[a] - 2);
      t[a] = s - T(c[a]);
    }
    const std::size_t base = index(c);
    std::array<std::size_t, 1 << D> k;
    bool all_identity = true;
    for (int corner = 0; corner < (1 << D); ++corner) {
      std::size_t i = base, stride = 1;
      for (int a = 0; a < D; ++a) {
        if (corner & (1 << a)) i += stride;
        stride *= std::size_t(n[a]);
      }
      k[std::size_t(corner)] = i;
      all_identity = all_identity && identity[i];
    }
    if (all_identity) return Mat<T, D>::Identity();
    Mat<T, D> out = Mat<T, D>::Zero();
    for (int corner = 0; corner < (1 << D); ++corner) {
      T w = T(1);
      for (int a = 0; a < D; ++a) w *= corner & (1 << a) ? t[a] : T(1) - t[a];
      out += w * fp_inv[k[std::size_t(corner)]];
    }
    return out;
  }
};

// Eq 35 at every sample with a plastic material: placed from its last y (kept where Newton
// fails), F = (∂X/∂y)⁻¹ there, F_e = F F_p⁻¹, and F_p⁻¹ ← F_p⁻¹ ΔF_p⁻¹ where eq 37 flows. F is in
// frame axes: the frame's rotation multiplies F_e from the left and changes neither Σ nor V.
template <class T, int D, class Material>
void update_plastic_samples(const EulerianGrid<T, D>& g, const std::vector<Material>& materials,
                            PlasticSamples<T, D>& s, bool parallel) {
  const std::ptrdiff_t count = std::ptrdiff_t(s.size());
  std::size_t flowed = 0;
  double det_error = 0;
#pragma omp parallel for if (parallel) reduction(+ : flowed) reduction(max : det_error)
  for (std::ptrdiff_t ii = 0; ii < count; ++ii) {
    const std::size_t i = std::size_t(ii);
    const std::int32_t m = s.material[i];
    if (m < 0) continue;
    const Vec<T, D> Z = s.position(i);
    Vec<T, D> p = s.y[i];
    const T tol = T(64) * std::numeric_limits<T>::epsilon() *
                  std::max(T(1), Z.template lpNorm<Eigen::Infinity>());
    if (!invert_reference_map(g, Z, tol, p)) continue;
    s.y[i] = p;
    Vec<T, D> X;
    Mat<T, D> J;
    g.interpolate_with_jacobian(g.X, p, X, J);
    const Material& mat = materials[std::size_t(m)];
    Mat<T, D> dFp_inv;
    if (!plastic_flow_step<T, D>(J.inverse() * s.fp_inv[i], mat.lame, mat.plastic, dFp_inv))
      continue;
    s.fp_inv[i] = (s.fp_inv[i] * dFp_inv).eval();
    s.identity[i] = 0;
    ++flowed;
    det_error = std::max(det_error, std::abs(double(dFp_inv.determinant()) - 1.0));
  }
  s.flowed = flowed;
  s.det_error = det_error;
}

}  // namespace apiclab::eol
