// The simplices of one object's world surface (segments in 2D, triangles in 3D) bucketed in a
// uniform grid over their box, for the contact rows between objects (object_contact.hpp,
// object_contact_3d.hpp): a simplex sits in every bucket its box meets, so a query box finds
// every simplex whose box meets it. Hand-written: a 40-line bucket grid over tens to thousands of
// simplices; a BVH or CGAL's box intersection would add a dependency for no gain at this size.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/math.hpp"

namespace apiclab::eol {

template <class T, int D>
class SimplexBuckets {
 public:
  using V = Vec<T, D>;
  void build(const std::vector<V>& x, const std::vector<std::uint32_t>& simplex) {
    x_ = &x;
    simplex_ = &simplex;
    const std::size_t count = simplex.size() / std::size_t(D);
    lo_ = V::Constant(T(INFINITY));
    hi_ = -lo_;
    T edge = T(0);
    for (std::size_t s = 0; s < count; ++s) {
      lo_ = lo_.cwiseMin(box_lo(s));
      hi_ = hi_.cwiseMax(box_hi(s));
      edge += (vertex(std::uint32_t(s), 1) - vertex(std::uint32_t(s), 0)).norm();
    }
    // Buckets about two edges wide, at most a few per simplex.
    h_ = count > 0 ? T(2) * edge / T(count) : T(1);
    if (!(h_ > T(0))) h_ = T(1);
    for (;;) {
      std::size_t cells = 1;
      for (int a = 0; a < D; ++a) {
        n_[std::size_t(a)] = count > 0 ? int(std::floor((hi_[a] - lo_[a]) / h_)) + 1 : 0;
        cells *= std::size_t(n_[std::size_t(a)]);
      }
      if (cells <= 4 * count + 64) break;
      h_ *= T(1.5);
    }
    std::size_t cells = 1;
    for (int a = 0; a < D; ++a) cells *= std::size_t(n_[std::size_t(a)]);
    start_.assign(cells + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {  // count per bucket, then fill
      if (pass == 1) {
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        item_.assign(start_.back(), 0);
      }
      std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
      for (std::size_t s = 0; s < count; ++s)
        visit(box_lo(s), box_hi(s), [&](std::size_t c) {
          if (pass == 0)
            ++start_[c + 1];
          else
            item_[fill[c]++] = std::uint32_t(s);
        });
    }
  }
  const V& lo() const { return lo_; }
  const V& hi() const { return hi_; }
  const V& vertex(std::uint32_t s, int k) const { return (*x_)[index(s, k)]; }
  std::uint32_t index(std::uint32_t s, int k) const {
    return (*simplex_)[std::size_t(D) * s + std::size_t(k)];
  }
  // The simplices in the buckets meeting [lo, hi], each once, into `out`.
  void candidates(const V& lo, const V& hi, std::vector<std::uint32_t>& out) const {
    out.clear();
    visit(lo, hi, [&](std::size_t c) {
      for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) out.push_back(item_[k]);
    });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

 protected:
  const std::vector<V>& x() const { return *x_; }

 private:
  V box_lo(std::size_t s) const {
    V b = vertex(std::uint32_t(s), 0);
    for (int k = 1; k < D; ++k) b = b.cwiseMin(vertex(std::uint32_t(s), k));
    return b;
  }
  V box_hi(std::size_t s) const {
    V b = vertex(std::uint32_t(s), 0);
    for (int k = 1; k < D; ++k) b = b.cwiseMax(vertex(std::uint32_t(s), k));
    return b;
  }
  // Calls f with every bucket meeting [lo, hi], x fastest.
  template <class F>
  void visit(const V& lo, const V& hi, F&& f) const {
    if (n_[0] == 0) return;
    std::array<int, D> c0, c1;
    for (int a = 0; a < D; ++a) {
      const T top = T(n_[std::size_t(a)] - 1);
      c0[std::size_t(a)] = int(std::clamp(std::floor((lo[a] - lo_[a]) / h_), T(0), top));
      c1[std::size_t(a)] = int(std::clamp(std::floor((hi[a] - lo_[a]) / h_), T(0), top));
    }
    std::array<int, D> c = c0;
    for (;;) {
      std::size_t flat = 0;
      for (int a = D - 1; a >= 0; --a)
        flat = flat * std::size_t(n_[std::size_t(a)]) + std::size_t(c[std::size_t(a)]);
      f(flat);
      std::size_t a = 0;
      for (; a < std::size_t(D) && c[a] == c1[a]; ++a) c[a] = c0[a];
      if (a == std::size_t(D)) return;
      ++c[a];
    }
  }
  const std::vector<V>* x_ = nullptr;
  const std::vector<std::uint32_t>* simplex_ = nullptr;
  V lo_, hi_;
  T h_ = T(1);
  std::array<int, D> n_{};
  std::vector<std::uint32_t> start_, item_;
};

}  // namespace apiclab::eol
