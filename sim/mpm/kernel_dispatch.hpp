// Run-time scene choices to compile-time types: one switch on the kernel for every phase, and
// the one test of whether a scheme carries the affine matrix C_p.
#pragma once
#include <utility>

#include "sim/mpm/kernels.hpp"
#include "sim/scene/registry.hpp"

namespace apiclab {

// f(LinearKernel{}), f(QuadraticKernel{}) or f(CubicKernel{}) as `type` says.
template <class Fn>
decltype(auto) with_kernel(KernelType type, Fn&& f) {
  switch (type) {
    case KernelType::linear:
      return std::forward<Fn>(f)(LinearKernel{});
    case KernelType::quadratic:
      return std::forward<Fn>(f)(QuadraticKernel{});
    case KernelType::cubic:
      break;
  }
  return std::forward<Fn>(f)(CubicKernel{});
}

// APIC, RPIC, MLS, TPIC and PolyPIC transfer v_p + C_p (x_i − x_p) (eq 24; PolyPIC adds its
// higher modes, sim/mpm/schemes/polypic.hpp); PIC and FLIP transfer v_p alone. ASFLIP (Fei et al.
// 2021) transfers as APIC; XPIC (Hammerquist and Nairn 2017) as PIC.
constexpr bool is_affine(Scheme s) {
  return s == Scheme::apic || s == Scheme::rpic || s == Scheme::mls || s == Scheme::asflip ||
         s == Scheme::tpic || s == Scheme::polypic;
}

}  // namespace apiclab
