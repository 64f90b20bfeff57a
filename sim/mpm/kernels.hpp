// B-spline interpolation kernels N(x) (Jiang et al. 2017, Sec 3.2; Steffen et al. 2008).
// Positions are in grid units (x / dx); the stencil is `width` nodes per axis starting at `base`.
// Weights w and their derivatives dw (per grid unit; divide by dx for ∇w) are per axis, and the
// multi-dimensional weight is their tensor product.
#pragma once
#include <cmath>

namespace apiclab {

// floor(x) as an int. The default is std::floor; TruncatingFloor gives the same value for
// |x| < 2³¹ through a conversion, which GCC vectorises across particles (it keeps std::floor
// scalar unless FP operations may be assumed not to trap) (sim/mpm/simd/stencil_batch.hpp).
struct StdFloor {
  template <class T>
  int operator()(T x) const {
    return int(std::floor(x));
  }
};
struct TruncatingFloor {
  template <class T>
  int operator()(T x) const {
    const int t = int(x);
    return t - int(T(t) > x);
  }
};

enum class KernelType { linear, quadratic, cubic };

struct LinearKernel {
  static constexpr int width = 2;
  static constexpr KernelType type = KernelType::linear;
  template <class T, class Floor = StdFloor>
  static int weights(T x, T* w, T* dw, Floor floor = {}) {
    int base = floor(x);
    T f = x - T(base);
    w[0] = T(1) - f;
    w[1] = f;
    dw[0] = T(-1);
    dw[1] = T(1);
    return base;
  }
};

struct QuadraticKernel {
  static constexpr int width = 3;
  static constexpr KernelType type = KernelType::quadratic;
  template <class T, class Floor = StdFloor>
  static int weights(T x, T* w, T* dw, Floor floor = {}) {
    int base = floor(x - T(0.5));
    T f = x - T(base);  // in [0.5, 1.5)
    T a = T(1.5) - f, b = f - T(1), c = f - T(0.5);
    w[0] = T(0.5) * a * a;
    w[1] = T(0.75) - b * b;
    w[2] = T(0.5) * c * c;
    dw[0] = -a;
    dw[1] = T(-2) * b;
    dw[2] = c;
    return base;
  }
};

struct CubicKernel {
  static constexpr int width = 4;
  static constexpr KernelType type = KernelType::cubic;
  template <class T, class Floor = StdFloor>
  static int weights(T x, T* w, T* dw, Floor floor = {}) {
    int base = floor(x) - 1;
    T f = x - T(base);  // in [1, 2)
    T a = T(2) - f, t1 = f - T(1), t2 = T(2) - f, d = f - T(1);
    w[0] = a * a * a / T(6);
    w[1] = T(0.5) * t1 * t1 * t1 - t1 * t1 + T(2) / T(3);
    w[2] = T(0.5) * t2 * t2 * t2 - t2 * t2 + T(2) / T(3);
    w[3] = d * d * d / T(6);
    dw[0] = T(-0.5) * a * a;
    dw[1] = T(1.5) * t1 * t1 - T(2) * t1;
    dw[2] = -(T(1.5) * t2 * t2 - T(2) * t2);
    dw[3] = T(0.5) * d * d;
    return base;
  }
};

// D_p = Σ w (x_i - x_p)(x_i - x_p)^T = k Δx² I for quadratic (k = 1/4) and cubic (k = 1/3)
// (Jiang et al. 2017, Sec 3.3); multilinear has no constant D_p (Sec 5.9).
inline double inertia_factor(KernelType k) {
  return k == KernelType::quadratic ? 0.25 : k == KernelType::cubic ? 1.0 / 3.0 : 0.0;
}

}  // namespace apiclab
