// The entries of `count` consecutive small vectors or matrices (n scalars each, column-major as
// Eigen stores them) as one register per entry, particle l in lane l, and back: how the stress
// pass (sim/mpm/simd/stress_lanes.hpp), the diagnostics row's sums (sim/mpm/particle_sums.hpp) and
// the float stencil batches (sim/mpm/simd/stencil_batch.hpp) read the particles' F, x, v and C
// several particles at a time. Lane by lane these moves were a third of the 2D and a quarter of the
// 3D stress pass.
#pragma once
#include <utility>

#include "sim/mpm/simd/lanes.hpp"

namespace apiclab {

namespace soa_transpose_detail {

template <class V>
inline constexpr int lane_count = int(sizeof(V) / sizeof(V{}[0]));

// Lane g·h + i of register k becomes lane g·h + k of register i, h lanes a 128-bit half: an h × h
// transpose within each half (unpacks and half moves, one instruction each on SSE, AVX2 and
// AVX-512); its own inverse.
template <class V, int h>
inline void transpose_within_halves(V (&r)[h]) {
  constexpr int count = lane_count<V>;
  if constexpr (count == 8) {
    const V t0 = shuffle_lanes<0, 8, 1, 9, 4, 12, 5, 13>(r[0], r[1]);  // unpack low
    const V t1 = shuffle_lanes<2, 10, 3, 11, 6, 14, 7, 15>(r[0], r[1]);
    const V t2 = shuffle_lanes<0, 8, 1, 9, 4, 12, 5, 13>(r[2], r[3]);
    const V t3 = shuffle_lanes<2, 10, 3, 11, 6, 14, 7, 15>(r[2], r[3]);
    r[0] = shuffle_lanes<0, 1, 8, 9, 4, 5, 12, 13>(t0, t2);  // low pairs of both
    r[1] = shuffle_lanes<2, 3, 10, 11, 6, 7, 14, 15>(t0, t2);
    r[2] = shuffle_lanes<0, 1, 8, 9, 4, 5, 12, 13>(t1, t3);
    r[3] = shuffle_lanes<2, 3, 10, 11, 6, 7, 14, 15>(t1, t3);
  } else if constexpr (count == 4 && h == 4) {  // 4 floats (SSE): one half
    const V t0 = shuffle_lanes<0, 4, 2, 6>(r[0], r[1]), t1 = shuffle_lanes<1, 5, 3, 7>(r[0], r[1]);
    const V t2 = shuffle_lanes<0, 4, 2, 6>(r[2], r[3]), t3 = shuffle_lanes<1, 5, 3, 7>(r[2], r[3]);
    r[0] = shuffle_lanes<0, 1, 4, 5>(t0, t2);
    r[1] = shuffle_lanes<0, 1, 4, 5>(t1, t3);
    r[2] = shuffle_lanes<2, 3, 6, 7>(t0, t2);
    r[3] = shuffle_lanes<2, 3, 6, 7>(t1, t3);
  } else if constexpr (count == 4) {  // 4 doubles (AVX): unpack low and high
    const V low = shuffle_lanes<0, 4, 2, 6>(r[0], r[1]);
    r[1] = shuffle_lanes<1, 5, 3, 7>(r[0], r[1]);
    r[0] = low;
  } else {  // 2 doubles (SSE)
    const V low = shuffle_lanes<0, 2>(r[0], r[1]);
    r[1] = shuffle_lanes<1, 3>(r[0], r[1]);
    r[0] = low;
  }
}

template <class V, class T, std::size_t... l>
inline V entry_of_each(const T* m, int n, std::index_sequence<l...>) {
  return V{m[n * int(l)]...};
}

// Pairs (n = 2) in two registers, [a0 b0 a1 b1 …]: the even lanes of both, or the odd ones.
template <int first, class V, std::size_t... l>
inline V every_other(const V& low, const V& high, std::index_sequence<l...>) {
  return shuffle_lanes<int(2 * l + first)...>(low, high);
}

}  // namespace soa_transpose_detail

// out[e] lane l = m[n l + e] for l < the lane count of V: entries e … e + h − 1 (h scalars a
// 128-bit half) come as h registers, register j holding in half g those entries of item
// j + g·h (one 128-bit load each, no cross-half shuffle), and a transpose within each half gives
// one register per entry; pairs (n = 2 with more than two scalars a half) are split into even and
// odd lanes; what is left of n (3D: entry 8 of a matrix, a 3-vector's entries) goes lane by lane.
template <int n, class V, class T>
inline void load_entries(const T* m, V (&out)[n]) {
  using namespace soa_transpose_detail;
  constexpr int count = lane_count<V>;
  constexpr int h = 16 / int(sizeof(T));
  constexpr int halves = count / h;
  using Half = typename SimdVector<T, h>::type;
  if constexpr (n == 2 && h > 2) {
    const V low = load_register<V>(m), high = load_register<V>(m + count);
    out[0] = every_other<0>(low, high, std::make_index_sequence<count>{});
    out[1] = every_other<1>(low, high, std::make_index_sequence<count>{});
  } else {
    constexpr int whole = n / h * h;
    for (int e = 0; e < whole; e += h) {
      V r[h];
      for (int j = 0; j < h; ++j) {
        if constexpr (halves == 1)
          r[j] = load_register<V>(m + n * j + e);
        else
          r[j] = join_halves<V>(load_register<Half>(m + n * j + e),
                                load_register<Half>(m + n * (j + h) + e));
      }
      transpose_within_halves(r);
      for (int k = 0; k < h; ++k) out[e + k] = r[k];
    }
    for (int e = whole; e < n; ++e)
      out[e] = entry_of_each<V>(m + e, n, std::make_index_sequence<count>{});
  }
}

// The reverse of load_entries for n a multiple of h or not (the rest lane by lane).
template <int n, class V, class T>
inline void store_entries(const V (&in)[n], T* m) {
  using namespace soa_transpose_detail;
  constexpr int count = lane_count<V>;
  constexpr int h = 16 / int(sizeof(T));
  constexpr int halves = count / h;
  using Half = typename SimdVector<T, h>::type;
  constexpr int whole = n / h * h;
  for (int e = 0; e < whole; e += h) {
    V r[h];
    for (int k = 0; k < h; ++k) r[k] = in[e + k];
    transpose_within_halves(r);
    for (int j = 0; j < h; ++j) {
      if constexpr (halves == 1) {
        store_register(m + n * j + e, r[j]);
      } else {
        store_register(m + n * j + e, half_of<0, Half>(r[j]));
        store_register(m + n * (j + h) + e, half_of<1, Half>(r[j]));
      }
    }
  }
  for (int e = whole; e < n; ++e)
    for (int l = 0; l < count; ++l) m[n * l + e] = in[e][l];
}

}  // namespace apiclab
