// The Eulerian grid of one object (Fan et al. 2013, Secs 3.1-3.3): a regular grid in the
// intermediate domain y that rides with the object's frame. Node fields: the material
// coordinates X (the reference map, φ₂⁻¹ of Fig 2), the Eulerian velocity v relative to the
// frame (frame axes), and the lumped mass m = ρ₀ det(∇X) H(φ₀(X)) Δx^d (eq 6 with J̄ = det ∇X;
// H smooths the rest shape's indicator φ₀ < 0 over one cell).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/math.hpp"

namespace apiclab::eol {

// Bytes a vector holds (its capacity): what the solver has allocated, for Fig 6's memory.
template <class V>
std::size_t held_bytes(const std::vector<V>& v) {
  return v.capacity() * sizeof(V);
}

template <class T, int D>
struct EulerianGrid {
  std::array<int, D> n{};                // nodes per axis
  T dx = T(1);                           // cell size
  Vec<T, D> origin = Vec<T, D>::Zero();  // y of node 0
  std::vector<Vec<T, D>> X, v;
  std::vector<T> mass, fill;           // fill = H(φ₀(X)) in [0, 1]
  std::vector<std::int32_t> material;  // the rest shape a node's X falls in (-1: none)

  void resize(const std::array<int, D>& nodes) {
    n = nodes;
    const std::size_t count = size();
    X.assign(count, Vec<T, D>::Zero());
    v.assign(count, Vec<T, D>::Zero());
    mass.assign(count, T(0));
    fill.assign(count, T(0));
    material.assign(count, -1);
  }
  std::size_t bytes() const {
    return held_bytes(X) + held_bytes(v) + held_bytes(mass) + held_bytes(fill) +
           held_bytes(material);
  }
  std::size_t size() const {
    std::size_t s = 1;
    for (int a = 0; a < D; ++a) s *= std::size_t(n[a]);
    return s;
  }
  std::size_t index(const std::array<int, D>& c) const {
    std::size_t i = std::size_t(c[D - 1]);
    for (int a = D - 2; a >= 0; --a) i = i * std::size_t(n[a]) + std::size_t(c[a]);
    return i;
  }
  std::array<int, D> coords(std::size_t i) const {
    std::array<int, D> c;
    for (int a = 0; a < D; ++a) {
      c[a] = int(i % std::size_t(n[a]));
      i /= std::size_t(n[a]);
    }
    return c;
  }
  std::size_t stride(int axis) const {
    std::size_t s = 1;
    for (int a = 0; a < axis; ++a) s *= std::size_t(n[a]);
    return s;
  }
  Vec<T, D> y(std::size_t i) const {
    const auto c = coords(i);
    Vec<T, D> out = origin;
    for (int a = 0; a < D; ++a) out[a] += dx * T(c[a]);
    return out;
  }
  // ∂f/∂y at node i (column a = ∂f/∂y_a): central differences, one-sided on the grid's faces;
  // exact for an affine f.
  Mat<T, D> gradient(const std::vector<Vec<T, D>>& f, std::size_t i) const {
    const auto c = coords(i);
    Mat<T, D> G;
    for (int a = 0; a < D; ++a) {
      const std::size_t s = stride(a);
      const std::size_t lo = c[a] > 0 ? i - s : i, hi = c[a] + 1 < n[a] ? i + s : i;
      const T span = dx * T((c[a] > 0) + (c[a] + 1 < n[a]));
      G.col(a) = span > T(0) ? Vec<T, D>((f[hi] - f[lo]) / span) : Vec<T, D>::Zero();
    }
    return G;
  }
  // The cell holding y (its lower corner c, clamped to the grid) and y's fraction t across it.
  // The clamp comes before the conversion to int: a state blowing up within a step (fuzz_scene
  // found one) gives NaN or ±∞ here, whose conversion is undefined; such a y takes an edge cell,
  // t carries the NaN on, and the step's blow-up check reports it.
  void cell_at(const Vec<T, D>& at, std::array<int, D>& c, std::array<T, D>& t) const {
    for (int a = 0; a < D; ++a) {
      const T u = (at[a] - origin[a]) / dx;
      const T lower = std::floor(u);
      const int top = std::max(n[a] - 2, 0);
      c[a] = lower >= T(top) ? top : lower > T(0) ? int(lower) : 0;
      t[a] = u - T(c[a]);
    }
  }
  // The multilinear weights at y and the nodes they weigh (corner c: bit a of c = +1 along a).
  struct CellWeights {
    std::array<std::size_t, 1 << D> index;
    std::array<T, 1 << D> weight;
  };
  CellWeights cell_weights(const Vec<T, D>& at) const {
    std::array<int, D> c;
    std::array<T, D> t;
    cell_at(at, c, t);
    CellWeights out;
    const std::size_t base = index(c);
    for (int corner = 0; corner < (1 << D); ++corner) {
      T w = T(1);
      std::size_t k = base;
      for (int a = 0; a < D; ++a) {
        const bool up = corner & (1 << a);
        w *= up ? t[a] : T(1) - t[a];
        if (up) k += stride(a);
      }
      out.index[std::size_t(corner)] = k;
      out.weight[std::size_t(corner)] = w;
    }
    return out;
  }
  // Multilinear interpolation of f at y. Outside the grid the nearest cell's multilinear form
  // is extended (its weights still reproduce affine fields), so an affine f is exact anywhere.
  template <class V>
  V interpolate(const std::vector<V>& f, const Vec<T, D>& at) const {
    const CellWeights cw = cell_weights(at);
    V out = f[0] * T(0);
    for (int corner = 0; corner < (1 << D); ++corner)
      out += cw.weight[std::size_t(corner)] * f[cw.index[std::size_t(corner)]];
    return out;
  }
  // The same multilinear interpolant of a vector field and its Jacobian ∂f/∂y there (column
  // a = ∂f/∂y_a, the derivative of the cell's multilinear form; exact for an affine f).
  void interpolate_with_jacobian(const std::vector<Vec<T, D>>& f, const Vec<T, D>& at,
                                 Vec<T, D>& value, Mat<T, D>& jacobian) const {
    std::array<int, D> c;
    std::array<T, D> t;
    cell_at(at, c, t);
    value.setZero();
    jacobian.setZero();
    for (int corner = 0; corner < (1 << D); ++corner) {
      std::array<T, D> w1;  // the corner's factor along each axis
      std::array<int, D> k = c;
      for (int a = 0; a < D; ++a) {
        const bool up = corner & (1 << a);
        w1[a] = up ? t[a] : T(1) - t[a];
        k[a] += up;
      }
      const Vec<T, D>& fk = f[index(k)];
      T w = T(1);
      for (int a = 0; a < D; ++a) w *= w1[a];
      value += w * fk;
      for (int a = 0; a < D; ++a) {
        T dw = (corner & (1 << a) ? T(1) : T(-1)) / dx;
        for (int b = 0; b < D; ++b)
          if (b != a) dw *= w1[b];
        jacobian.col(a) += dw * fk;
      }
    }
  }
};

// The smoothed indicator H(φ) of the rest shape: 1 inside, 0 outside, linear across one cell
// width h around φ = 0 (a node is a cell's worth of material, split by the surface).
template <class T>
T smoothed_inside(double phi, double h) {
  return T(std::clamp(0.5 - phi / h, 0.0, 1.0));
}

}  // namespace apiclab::eol
