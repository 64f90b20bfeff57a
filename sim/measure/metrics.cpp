#include "sim/measure/metrics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>

#include "sim/measure/run_summary.hpp"

namespace apiclab::metrics {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double norm3(const std::array<double, 3>& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

// nanoflann's view of one object's material points (frame 0 positions).
struct PointCloud {
  const std::vector<double>* positions;
  std::vector<std::uint32_t> ids;  // particle index of each point
  int dim;
  std::size_t kdtree_get_point_count() const { return ids.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t a) const {
    return (*positions)[std::size_t(ids[i]) * std::size_t(dim) + a];
  }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

template <int D>
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                 PointCloud, D, std::uint32_t>;

}  // namespace

Conservation conservation(const std::vector<DiagnosticsRow>& rows, const DriftRule& drift) {
  Conservation c;
  if (rows.empty()) return c;
  c.angular_relative = drift.angular_momentum_relative();
  c.energy_relative = drift.energy_relative();
  for (const DiagnosticsRow& r : rows) {
    const double dE = std::abs(drift.energy(r)), dL = drift.angular_momentum(r);
    const std::array<double, 3> dp{r.p[0] - rows.front().p[0], r.p[1] - rows.front().p[1],
                                   r.p[2] - rows.front().p[2]};
    // A NaN drift (a state gone non-finite) is the largest drift of all.
    c.max_energy = std::isnan(dE) ? dE : std::max(c.max_energy, dE);
    c.max_angular = std::isnan(dL) ? dL : std::max(c.max_angular, dL);
    c.max_momentum = std::isnan(norm3(dp)) ? norm3(dp) : std::max(c.max_momentum, norm3(dp));
    c.final_energy = dE;
    c.final_angular = dL;
    c.final_momentum = norm3(dp);
  }
  return c;
}

int RunFrames::object_count() const {
  int n = 0;
  for (std::int32_t o : object) n = std::max(n, int(o) + 1);
  return n;
}

std::vector<std::array<double, 3>> centres_of_mass(const RunFrames& run, const Frame& frame) {
  const int n_obj = run.object_count();
  std::vector<std::array<double, 3>> c(std::size_t(n_obj), {0, 0, 0});
  std::vector<double> count(std::size_t(n_obj), 0);
  for (std::size_t q = 0; q < run.count(); ++q) {
    const auto o = std::size_t(run.object[q]);
    for (int a = 0; a < run.dim; ++a)
      c[o][std::size_t(a)] += frame.positions[q * std::size_t(run.dim) + std::size_t(a)];
    count[o] += 1;
  }
  for (std::size_t o = 0; o < c.size(); ++o)
    for (double& v : c[o]) v /= std::max(count[o], 1.0);
  return c;
}

double relative_l2(const std::vector<double>& a, const std::vector<double>& b, double floor) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    num += (a[i] - b[i]) * (a[i] - b[i]);
    den += b[i] * b[i];
  }
  if (a.size() != b.size()) return kNaN;
  return std::sqrt(num) / std::max(std::sqrt(den), floor);
}

DisplacementInterpolator::DisplacementInterpolator(const RunFrames& from, const RunFrames& at)
    : dim_(at.dim) {
  const int D = at.dim;
  const std::size_t k_wanted = D == 2 ? 8 : 16;
  const std::vector<double>& X_from = from.frames.front().positions;
  const std::vector<double>& X_at = at.frames.front().positions;
  std::vector<PointCloud> clouds(std::size_t(std::max(from.object_count(), at.object_count())),
                                 PointCloud{&X_from, {}, D});
  for (std::size_t q = 0; q < from.count(); ++q)
    clouds[std::size_t(from.object[q])].ids.push_back(std::uint32_t(q));
  std::vector<std::vector<Term>> per_point(at.count());
  for (std::size_t o = 0; o < clouds.size(); ++o) {
    const PointCloud& cloud = clouds[o];
    if (cloud.ids.empty()) continue;
    auto interpolate = [&](auto& tree) {
      const std::size_t k = std::min(k_wanted, cloud.ids.size());
      std::vector<std::uint32_t> idx(k);
      std::vector<double> d2(k);
      for (std::size_t q = 0; q < at.count(); ++q) {
        if (std::size_t(at.object[q]) != o) continue;
        const double* Xq = &X_at[q * std::size_t(D)];
        const std::size_t found = tree.knnSearch(Xq, k, idx.data(), d2.data());
        // Weighted least squares on the basis [1, X − X*]: the value at X* is the first
        // coefficient, Σ c_j u_j with c = W A (Aᵀ W A)⁻¹ e₁.
        const double h2 = std::max(d2[found - 1], 1e-300);
        Eigen::MatrixXd A(found, D + 1);
        Eigen::VectorXd w(found);
        for (std::size_t j = 0; j < found; ++j) {
          A(Eigen::Index(j), 0) = 1;
          for (int a = 0; a < D; ++a)
            A(Eigen::Index(j), a + 1) =
                X_from[std::size_t(cloud.ids[idx[j]]) * std::size_t(D) + std::size_t(a)] - Xq[a];
          w(Eigen::Index(j)) = 1.0 / (d2[j] + 0.01 * h2);
        }
        const Eigen::MatrixXd M = A.transpose() * w.asDiagonal() * A;
        Eigen::VectorXd e1 = Eigen::VectorXd::Zero(D + 1);
        e1(0) = 1;
        Eigen::VectorXd c;
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
        if (d2[0] <= 1e-24 * h2) {  // the same material point: its own displacement
          c = Eigen::VectorXd::Zero(Eigen::Index(found));
          c(0) = 1;
        } else if (found > std::size_t(D) && lu.rank() == D + 1 && lu.rcond() > 1e-10) {
          c = w.asDiagonal() * (A * lu.solve(e1));
        } else {  // collinear or too few neighbours: the weighted mean
          c = w / w.sum();
        }
        for (std::size_t j = 0; j < found; ++j)
          per_point[q].push_back({cloud.ids[idx[j]], c(Eigen::Index(j))});
      }
    };
    if (D == 2) {
      Tree<2> tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
      interpolate(tree);
    } else {
      Tree<3> tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
      interpolate(tree);
    }
  }
  begin_.assign(at.count() + 1, 0);
  for (std::size_t q = 0; q < at.count(); ++q) {
    begin_[q] = std::uint32_t(terms_.size());
    terms_.insert(terms_.end(), per_point[q].begin(), per_point[q].end());
  }
  begin_[at.count()] = std::uint32_t(terms_.size());
}

std::vector<double> DisplacementInterpolator::displacement(const RunFrames& from,
                                                           std::size_t f) const {
  const std::size_t D = std::size_t(dim_), n = begin_.size() - 1;
  const std::vector<double>& x = from.frames[f].positions;
  const std::vector<double>& X = from.frames.front().positions;
  std::vector<double> u(n * D, 0.0);
  for (std::size_t q = 0; q < n; ++q) {
    if (begin_[q] == begin_[q + 1]) {  // no particles of this object in `from`
      for (std::size_t a = 0; a < D; ++a) u[q * D + a] = kNaN;
      continue;
    }
    for (std::uint32_t t = begin_[q]; t < begin_[q + 1]; ++t) {
      const std::size_t p = terms_[t].particle;
      for (std::size_t a = 0; a < D; ++a)
        u[q * D + a] += terms_[t].weight * (x[p * D + a] - X[p * D + a]);
    }
  }
  return u;
}

ReferenceDistance reference_distance(const RunFrames& run, const RunFrames& ref) {
  const ReferenceDistance none{kNaN, kNaN, kNaN, kNaN, kNaN};
  if (run.frames.size() != ref.frames.size() || ref.frames.empty() || run.dim != ref.dim ||
      run.object_count() != ref.object_count())
    return none;
  for (std::size_t f = 0; f < ref.frames.size(); ++f)
    if (std::abs(run.frames[f].t - ref.frames[f].t) > 1e-9 * std::max(1.0, ref.frames[f].t))
      return none;
  const std::size_t D = std::size_t(ref.dim), F = ref.frames.size();
  ReferenceDistance d;
  // Centre of mass, relative to the RMS radius of each reference body about its centre.
  const auto c0 = centres_of_mass(ref, ref.frames.front());
  std::vector<double> radius2(c0.size(), 0), count(c0.size(), 0);
  for (std::size_t q = 0; q < ref.count(); ++q) {
    const auto o = std::size_t(ref.object[q]);
    for (std::size_t a = 0; a < D; ++a) {
      const double r = ref.frames.front().positions[q * D + a] - c0[o][a];
      radius2[o] += r * r;
    }
    count[o] += 1;
  }
  double size2 = 0;
  for (std::size_t o = 0; o < c0.size(); ++o) size2 += radius2[o] / std::max(count[o], 1.0);
  double com_num = 0;
  std::vector<double> K, K_ref, P, P_ref, E_ref;
  for (std::size_t f = 0; f < F; ++f) {
    const auto c = centres_of_mass(run, run.frames[f]);
    const auto c_ref = centres_of_mass(ref, ref.frames[f]);
    for (std::size_t o = 0; o < c.size(); ++o)
      for (std::size_t a = 0; a < D; ++a)
        com_num += (c[o][a] - c_ref[o][a]) * (c[o][a] - c_ref[o][a]);
    K.push_back(run.frames[f].kinetic);
    K_ref.push_back(ref.frames[f].kinetic);
    P.push_back(run.frames[f].elastic);
    P_ref.push_back(ref.frames[f].elastic);
    E_ref.push_back(ref.frames[f].kinetic + ref.frames[f].elastic);
  }
  d.com = std::sqrt(com_num / (double(F) * std::max(size2, 1e-300)));
  d.kinetic = relative_l2(K, K_ref, 1e-300);
  // Elastic energy against the reference's energy scale K + Ψ: Ψ_ref alone can be ~0 (a rigid
  // rotation stores almost none).
  double p_num = 0, e_den = 0;
  for (std::size_t f = 0; f < F; ++f) {
    p_num += (P[f] - P_ref[f]) * (P[f] - P_ref[f]);
    e_den += E_ref[f] * E_ref[f];
  }
  d.elastic = std::sqrt(p_num) / std::max(std::sqrt(e_den), 1e-300);
  // Displacement x − X at the reference's material points.
  const DisplacementInterpolator interp(run, ref);
  double u_num = 0, u_den = 0;
  for (std::size_t f = 0; f < F; ++f) {
    const std::vector<double> u = interp.displacement(run, f);
    const std::vector<double>& x = ref.frames[f].positions;
    const std::vector<double>& X = ref.frames.front().positions;
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double u_ref = x[i] - X[i];
      u_num += (u[i] - u_ref) * (u[i] - u_ref);
      u_den += u_ref * u_ref;
    }
  }
  d.displacement = std::sqrt(u_num) / std::max(std::sqrt(u_den), 1e-300);
  d.displacement_rms = std::sqrt(u_num / double(F * ref.count()));
  return d;
}

double rigid_motion_distance(const RunFrames& run, const std::vector<RigidMotion>& motions) {
  if (run.frames.empty() || int(motions.size()) < run.object_count()) return kNaN;
  const std::size_t D = std::size_t(run.dim);
  const std::vector<double>& X = run.frames.front().positions;
  double num = 0, den = 0;
  for (const Frame& f : run.frames) {
    for (std::size_t q = 0; q < run.count(); ++q) {
      const RigidMotion& m = motions[std::size_t(run.object[q])];
      Eigen::Vector3d r(0, 0, 0), axis(0, 0, 1);
      for (std::size_t a = 0; a < D; ++a) r[Eigen::Index(a)] = X[q * D + a] - m.centre[a];
      double angle = m.omega[2] * f.t;
      if (D == 3) {
        const Eigen::Vector3d w(m.omega[0], m.omega[1], m.omega[2]);
        angle = w.norm() * f.t;
        if (w.norm() > 0) axis = w.normalized();
      }
      const Eigen::Vector3d rotated = Eigen::AngleAxisd(angle, axis) * r;
      for (std::size_t a = 0; a < D; ++a) {
        const double u_exact = rotated[Eigen::Index(a)] - r[Eigen::Index(a)] + m.velocity[a] * f.t;
        const double u = f.positions[q * D + a] - X[q * D + a];
        num += (u - u_exact) * (u - u_exact);
        den += u_exact * u_exact;
      }
    }
  }
  return std::sqrt(num) / std::max(std::sqrt(den), 1e-300);
}

double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    n += 1;
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double den = n * sxx - sx * sx;
  if (n < 2 || den <= 0) return kNaN;
  return (n * sxy - sx * sy) / den;
}

}  // namespace apiclab::metrics
