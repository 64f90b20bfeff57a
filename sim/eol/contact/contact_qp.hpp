// The contact QP of Fan et al. 2013, eq 29, with the lumped (diagonal) mass:
//   minimise ½ (u − u*)ᵀ M (u − u*)   subject to  J u ≤ r (unilateral rows), J u = r (bilateral),
// u* the velocities after the impulse (eq 16), r = J v_b the rates of a moving body's rows (zero
// elsewhere). Its dual on the m rows is the LCP
//   u = u* − M⁻¹Jᵀλ,  w = J u − r = b − Aλ,  A = J M⁻¹ Jᵀ,  b = J u* − r,
//   unilateral: λ ≥ 0, w ≤ 0, λ w = 0;  bilateral: w = 0.
// Nodes without mass are not unknowns (their velocities are the extrapolated field, held fixed):
// their terms go into b only. A is small and dense (m is tens of rows), so it is assembled and
// solved by projected Gauss–Seidel, then polished by the primal–dual active set the paper uses
// (Ito and Kunisch 2008): on the rows PGS left active, A_SS λ_S = b_S solved exactly (LDLT),
// accepted when it is feasible, so the KKT conditions hold to round-off. Written by hand: Eigen
// has no QP and a dense m × m LCP is 60 lines (Debian's QP libraries are sparse interior-point
// solvers for much larger problems).
#pragma once
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/eol/contact/surface_contact.hpp"

namespace apiclab::eol {

struct ContactSolveStats {
  int rows = 0, active = 0, sweeps = 0;
  bool polished = false;
  double max_violation = 0;  // max over rows of w (unilateral) or |w| (bilateral), after
  double seconds = 0;        // the solve's wall time, where the caller times it
};

template <class T, int D>
class ContactSolver {
 public:
  // Solves eq 29 for `u` in place (u holds u* on entry). mass: the lumped node masses.
  ContactSolveStats solve(const ContactRows<T, D>& J, const std::vector<T>& mass,
                          std::vector<Vec<T, D>>& u) {
    ContactSolveStats st;
    const int m = int(J.rows());
    st.rows = m;
    if (m == 0) return st;
    // b = J u* (every node), and per node its rows with mass: the entries bucketed by node (a
    // counting sort, linear in the entries: a comparison sort of the tens of thousands of
    // quadrature entries of a face lying on a plane cost more than the rest of the solve).
    rates(J, u);
    start_.assign(mass.size() + 1, 0);
    for (std::size_t e = 0; e < J.row.size(); ++e)
      if (mass[J.node[e]] > T(0)) ++start_[J.node[e] + 1];
    for (std::size_t i = 0; i < mass.size(); ++i) start_[i + 1] += start_[i];
    order_.resize(start_.back());
    for (std::size_t e = 0; e < J.row.size(); ++e)
      if (mass[J.node[e]] > T(0)) order_[start_[J.node[e]]++] = std::uint32_t(e);
    // One entry per (node, row): the quadrature points' terms summed in their order.
    node_.clear();
    row_.clear();
    coeff_.clear();
    std::size_t first = 0;  // the current node's first merged entry
    for (std::uint32_t e : order_) {
      if (node_.empty() || node_.back() != J.node[e]) first = node_.size();
      std::size_t k = first;
      while (k < node_.size() && row_[k] != J.row[e]) ++k;
      if (k < node_.size()) {
        coeff_[k] += J.coeff[e];
        continue;
      }
      node_.push_back(J.node[e]);
      row_.push_back(J.row[e]);
      coeff_.push_back(J.coeff[e]);
    }
    A_.setZero(m, m);
    for (std::size_t s = 0; s < node_.size();) {
      std::size_t end = s;
      while (end < node_.size() && node_[end] == node_[s]) ++end;
      const double inv_m = 1.0 / double(mass[node_[s]]);
      for (std::size_t a = s; a < end; ++a)
        for (std::size_t c = s; c < end; ++c)
          A_(row_[a], row_[c]) += inv_m * double(coeff_[a].dot(coeff_[c]));
      s = end;
    }
    dual(J.bilateral, st);
    // u = u* − M⁻¹ Jᵀ λ.
    for (std::size_t e = 0; e < node_.size(); ++e) {
      const double l = lambda_[row_[e]];
      if (l != 0.0) u[node_[e]] -= T(l / double(mass[node_[e]])) * coeff_[e];
    }
    for (int k = 0; k < m; ++k) st.active += lambda_[k] != 0.0;
    rates(J, u);  // now J u − r, for the violation
    for (int k = 0; k < m; ++k)
      if (usable_[std::size_t(k)])
        st.max_violation =
            std::max(st.max_violation, J.bilateral[std::size_t(k)] ? std::abs(b_[std::size_t(k)])
                                                                   : b_[std::size_t(k)]);
    return st;
  }
  const Eigen::VectorXd& multipliers() const { return lambda_; }

  // The dual LCP alone, on a given A (m × m, symmetric positive semi-definite) and b: λ with
  // w = b − Aλ, λ ≥ 0, w ≤ 0, λ w = 0 on the unilateral rows and w = 0 on the bilateral ones.
  // Backward Euler with contact (implicit_contact.hpp) passes A = J H⁻¹ Jᵀ.
  const Eigen::VectorXd& solve_dual(const Eigen::MatrixXd& A, const std::vector<double>& b,
                                    const std::vector<std::uint8_t>& bilateral,
                                    ContactSolveStats& st) {
    A_ = A;
    b_ = b;
    st.rows = int(b.size());
    dual(bilateral, st);
    st.active = int((lambda_.array() != 0.0).count());
    return lambda_;
  }

 private:
  // Projected Gauss–Seidel on the dual (A_, b_), then the active-set polish.
  void dual(const std::vector<std::uint8_t>& bilateral, ContactSolveStats& st) {
    const int m = int(b_.size());
    // Rows no node with mass can move are left out (λ = 0): nothing can enforce them.
    double diag_max = 0;
    for (int k = 0; k < m; ++k) diag_max = std::max(diag_max, A_(k, k));
    usable_.assign(std::size_t(m), 0);
    for (int k = 0; k < m; ++k) usable_[std::size_t(k)] = A_(k, k) > 1e-12 * diag_max;
    lambda_.setZero(m);
    const double tol = 1e-15 * (diag_max > 0 ? 1.0 : 0.0);
    // A's nonzeros by column (A is symmetric, so a column is a row): a row meets only the rows
    // that share a node with it, so a sweep costs the nonzeros, not m² (a face lying on a plane
    // has hundreds of rows and the sweeps were most of its step).
    col_start_.assign(std::size_t(m) + 1, 0);
    col_row_.clear();
    col_value_.clear();
    for (int k = 0; k < m; ++k) {
      for (int j = 0; j < m; ++j)
        if (A_(j, k) != 0.0) {
          col_row_.push_back(j);
          col_value_.push_back(A_(j, k));
        }
      col_start_[std::size_t(k) + 1] = col_row_.size();
    }
    // Projected Gauss–Seidel on the dual, to a relative step of 1e-12 or 2000 sweeps.
    double b_scale = 0;  // max |b|
    for (double v : b_) b_scale = std::max(b_scale, std::abs(v));
    for (st.sweeps = 0; st.sweeps < 2000; ++st.sweeps) {
      double change = 0;
      for (int k = 0; k < m; ++k) {
        if (!usable_[std::size_t(k)]) continue;
        double w = b_[std::size_t(k)];
        for (std::size_t e = col_start_[std::size_t(k)]; e < col_start_[std::size_t(k) + 1]; ++e)
          w -= col_value_[e] * lambda_[col_row_[e]];
        double l = lambda_[k] + w / A_(k, k);
        if (!bilateral[std::size_t(k)]) l = std::max(l, 0.0);
        change = std::max(change, std::abs(l - lambda_[k]) * A_(k, k));
        lambda_[k] = l;
      }
      if (change <= 1e-12 * b_scale + tol) break;
    }
    polish(bilateral, b_scale, st);
  }

  // The active set S (bilateral rows, and unilateral rows with λ > 0): A_SS λ_S = b_S exactly;
  // kept when λ_S ≥ 0 on the unilateral rows and w ≤ 0 off S (up to round-off of b).
  // b = J u − r, every row's rate relative to its body.
  void rates(const ContactRows<T, D>& J, const std::vector<Vec<T, D>>& u) {
    b_.assign(J.rows(), 0.0);
    for (std::size_t k = 0; k < J.rate.size(); ++k) b_[k] = -double(J.rate[k]);
    for (std::size_t e = 0; e < J.row.size(); ++e)
      b_[J.row[e]] += double(J.coeff[e].dot(u[J.node[e]]));
  }

  // b_scale: max |b|, as solve() computed it.
  void polish(const std::vector<std::uint8_t>& bilateral, double b_scale, ContactSolveStats& st) {
    const int m = int(b_.size());
    active_.clear();
    for (int k = 0; k < m; ++k)
      if (usable_[std::size_t(k)] && (bilateral[std::size_t(k)] || lambda_[k] > 0))
        active_.push_back(k);
    if (active_.empty()) return;
    const int s = int(active_.size());
    Eigen::MatrixXd As(s, s);
    Eigen::VectorXd bs(s);
    for (int a = 0; a < s; ++a) {
      bs[a] = b_[std::size_t(active_[std::size_t(a)])];
      for (int c = 0; c < s; ++c) As(a, c) = A_(active_[std::size_t(a)], active_[std::size_t(c)]);
    }
    const Eigen::VectorXd ls = As.ldlt().solve(bs);
    Eigen::VectorXd trial = Eigen::VectorXd::Zero(m);
    for (int a = 0; a < s; ++a) trial[active_[std::size_t(a)]] = ls[a];
    if (!trial.allFinite()) return;
    const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(b_.data(), m) - A_ * trial;
    const double eps = 1e-10 * b_scale;
    for (int k = 0; k < m; ++k) {
      if (!usable_[std::size_t(k)] || bilateral[std::size_t(k)]) continue;
      if (trial[k] < 0 || (trial[k] == 0 && w[k] > eps)) return;
    }
    lambda_ = trial;
    st.polished = true;
  }

  std::vector<double> b_;
  std::vector<std::uint32_t> order_, node_, row_, start_;
  std::vector<Vec<T, D>> coeff_;
  std::vector<char> usable_;
  std::vector<int> active_, col_row_;
  std::vector<std::size_t> col_start_;
  std::vector<double> col_value_;
  Eigen::MatrixXd A_;
  Eigen::VectorXd lambda_;
};

}  // namespace apiclab::eol
