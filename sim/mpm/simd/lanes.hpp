// Per-node lane groups for P2G and G2P: a few values of one grid node held as whole SIMD
// registers of the target (GCC/Clang vector extension, no intrinsics). A group wider than a
// register is split into register-sized parts with explicit per-part operations: a single
// 512-bit vector of doubles on an AVX2 target is lowered through the stack (scalar stores, then
// vector reloads), which made double on AVX2 several times slower than float.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

namespace apiclab {

// Bytes of the vector registers the lane groups fill: 32 with AVX, also where AVX-512 has 64.
// With 64 double ran slower and float the same: 512-bit arithmetic lowers the core's clock
// (docs/performance.md).
// The same width on both builds also gives the native and the x86-64-v3 build one layout. The
// native build holds GCC's own vectoriser to it too (-mprefer-vector-width=256, CMakeLists.txt).
#if defined(__AVX__)
inline constexpr int simd_register_bytes = 32;
#else
inline constexpr int simd_register_bytes = 16;
#endif

// Vector registers of the target: AVX-512VL gives 256-bit operations 32, AVX2 16.
#if defined(__AVX512VL__)
inline constexpr int simd_register_count = 32;
#else
inline constexpr int simd_register_count = 16;
#endif

// One register of P values. Spelled per scalar and width because the attribute is lost on a
// dependent typedef.
template <class T, int P>
struct SimdVector;
#define APICLAB_SIMD_VECTOR(T, I, P)                             \
  template <>                                                    \
  struct SimdVector<T, P> {                                      \
    typedef T type __attribute__((vector_size(P * sizeof(T))));  \
    typedef I index __attribute__((vector_size(P * sizeof(T)))); \
  };
APICLAB_SIMD_VECTOR(float, std::int32_t, 4)
APICLAB_SIMD_VECTOR(float, std::int32_t, 8)
APICLAB_SIMD_VECTOR(double, std::int64_t, 2)
APICLAB_SIMD_VECTOR(double, std::int64_t, 4)
APICLAB_SIMD_VECTOR(double, std::int64_t, 8)
#undef APICLAB_SIMD_VECTOR

// Lanes picked from two registers of P lanes by index (0..P−1 from a, P..2P−1 from b; a and b
// the same register to pick from one), one index per result lane: the one spelling of GCC's and
// Clang's builtins.
template <int... idx, class V>
inline V shuffle_lanes(V a, V b) {
#if defined(__clang__)
  return __builtin_shufflevector(a, b, idx...);
#else
  using Index = decltype(a < b);  // the signed integer vector of V's shape
  return __builtin_shuffle(a, b, Index{idx...});
#endif
}

// Every lane s, as one broadcast: s − 0 is s for every s (−0 − 0 = −0), so GCC folds it away;
// V{} + s it must keep (0 + −0 = +0), and a lane-by-lane fill it builds with one insert a lane.
template <class V, class T>
inline V splat(T s) {
  return s - V{};
}

// A register from its two halves, and one half of a register (GCC 12 and Clang both have
// __builtin_shufflevector, which may change the lane count; __builtin_shuffle may not).
template <class V, class Half>
inline V join_halves(Half low, Half high) {
  static_assert(2 * sizeof(Half) == sizeof(V));
  if constexpr (sizeof(Half) / sizeof(low[0]) == 4)
    return __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7);
  else
    return __builtin_shufflevector(low, high, 0, 1, 2, 3);
}
template <int g, class Half, class V>
inline Half half_of(V v) {
  static_assert(2 * sizeof(Half) == sizeof(V) && (g == 0 || g == 1));
  if constexpr (sizeof(Half) / sizeof(v[0]) == 4)
    return __builtin_shufflevector(v, v, 4 * g, 4 * g + 1, 4 * g + 2, 4 * g + 3);
  else
    return __builtin_shufflevector(v, v, 2 * g, 2 * g + 1);
}

// One register of lanes read from, or written to, consecutive scalars (memcpy: no alignment
// asked). One call per register: a copy of several registers at once GCC may stage on the stack
// in 16-byte pieces, whose whole-register reloads then stall store forwarding.
template <class V, class T>
inline V load_register(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V, class T>
inline void store_register(T* p, const V& v) {
  std::memcpy(p, &v, sizeof v);
}

// Lanes<T, used>'s lanes per register and registers.
template <class T>
constexpr int lanes_per_part(int used, int register_bytes = simd_register_bytes) {
  return std::min({8, register_bytes / int(sizeof(T)), int(std::bit_ceil(unsigned(used)))});
}
// Lanes<T, used>::parts, without naming the type (Lanes of two floats has no vector type).
template <class T>
constexpr int lane_parts(int used, int register_bytes = simd_register_bytes) {
  return (used + lanes_per_part<T>(used, register_bytes) - 1) /
         lanes_per_part<T>(used, register_bytes);
}

// At least `used` values as `parts` registers of `per_part` lanes each, no wider than needed
// (G2P's 4 lanes of a 2D double node are one 256-bit register also on AVX-512, where a 512-bit
// one costs two). Lane i lives in part i / per_part, and the parts are contiguous, so the first
// lanes of a group in memory are a smaller group (prefix_of). The register width is a parameter
// so that tests can check every layout on any machine.
template <class T, int used, int register_bytes = simd_register_bytes>
struct Lanes {
  static constexpr int per_part = lanes_per_part<T>(used, register_bytes);
  static constexpr int parts = (used + per_part - 1) / per_part;
  static constexpr int count = parts * per_part;
  using Part = typename SimdVector<T, per_part>::type;
  Part part[parts];

  // The lanes (v_0, v_1, …), zero after the given ones; built in registers, not lane by lane
  // through memory.
  template <class... V>
  static Lanes of(V... v) {
    static_assert(sizeof...(V) <= count);
    const T values[count] = {T(v)...};
    return from_array(values, std::make_index_sequence<parts>{});
  }
  // The first lanes of a wider group: one load per part (a copy of the whole group through
  // memcpy went through the stack as 16-byte pieces, and reloading them stalled store forwarding).
  template <int wider>
  static Lanes prefix_of(const Lanes<T, wider, register_bytes>& w) {
    using Wide = Lanes<T, wider, register_bytes>;
    static_assert(count <= Wide::count);
    Lanes out;
    if constexpr (Wide::per_part == per_part) {
      for (int k = 0; k < parts; ++k) out.part[k] = w.part[k];
    } else {
      const char* bytes = reinterpret_cast<const char*>(&w);
      for (int k = 0; k < parts; ++k)
        std::memcpy(&out.part[k], bytes + k * sizeof(Part), sizeof(Part));
    }
    return out;
  }
  T operator[](int i) const { return part[i / per_part][i % per_part]; }

  Lanes& operator+=(const Lanes& o) {
    for (int k = 0; k < parts; ++k) part[k] += o.part[k];
    return *this;
  }
  friend Lanes operator+(Lanes a, const Lanes& b) { return a += b; }
  friend Lanes operator-(Lanes a, const Lanes& b) {
    for (int k = 0; k < parts; ++k) a.part[k] -= b.part[k];
    return a;
  }
  friend Lanes operator*(Lanes a, const Lanes& b) {
    for (int k = 0; k < parts; ++k) a.part[k] *= b.part[k];
    return a;
  }
  friend Lanes operator*(T s, Lanes a) {
    for (int k = 0; k < parts; ++k) a.part[k] *= s;
    return a;
  }

  // (v_i, v_j, v_k, …): three lanes brought to the front (the rest unspecified). The builtins
  // spelled here, not through shuffle_lanes: that changed GCC's inlining in 2D double G2P on
  // x86-64-v3 into more, slower instructions.
  template <int i, int j, int k>
  Lanes front3() const {
    static_assert(i < count && j < count && k < count);
    if constexpr (parts == 1 && per_part >= 4) {
#if defined(__clang__)
      if constexpr (per_part == 4)
        return {__builtin_shufflevector(part[0], part[0], i, j, k, k)};
      else
        return {__builtin_shufflevector(part[0], part[0], i, j, k, k, k, k, k, k)};
#else
      using Mask = typename SimdVector<T, per_part>::index;
      return {__builtin_shuffle(part[0], Mask{i, j, k, k})};
#endif
    } else {
      return of((*this)[i], (*this)[j], (*this)[k]);
    }
  }

 private:
  template <std::size_t... k>
  static Lanes from_array(const T* values, std::index_sequence<k...>) {
    return {{part_from(values + k * per_part, std::make_index_sequence<per_part>{})...}};
  }
  template <std::size_t... e>
  static Part part_from(const T* values, std::index_sequence<e...>) {
    return Part{values[e]...};
  }
};

}  // namespace apiclab
