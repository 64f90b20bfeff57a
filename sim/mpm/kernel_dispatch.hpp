// Run-time scene choices to compile-time types: one switch on the kernel and one on the transfer
// scheme for every phase.
#pragma once
#include <type_traits>
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

// f(std::integral_constant<Scheme, S>{}) for the scheme `s`: the one scheme switch, over every
// line of sim/scene/scheme_registry.hpp; scheme_t<S> is the scheme's file.
template <int I = 0, class Fn>
decltype(auto) with_scheme(Scheme s, Fn&& f) {
  if constexpr (I + 1 < kSchemeCount)
    if (s != Scheme(I)) return with_scheme<I + 1>(s, std::forward<Fn>(f));
  return std::forward<Fn>(f)(std::integral_constant<Scheme, Scheme(I)>{});
}

}  // namespace apiclab
