// Contact inside backward Euler (solver.elasticity implicit, solver.contact surface): the rows
// of eq 28 depend on the placed surfaces only, so they are built from the step's start before
// the elastic solve, which then minimises
//   Σ_objects E(w)   subject to   J u ≤ r,  u = R w,
// E the backward Euler energy of implicit_elasticity.hpp. Its KKT conditions are backward Euler
// with the impulse −Jᵀλ, m (w − ũ) = Δt f_e(y + Δt w) − Rᵀ Jᵀλ, and eq 29's complementarity.
// Solved by alternating: the Newton solve at fixed λ, then λ from the dual LCP of the model
// linearised at that w, A = J R H⁻¹ Rᵀ Jᵀ (H = M + Δt² K, the stiffness spreading the impulse
// through the object) and b = J u − r + A λ, until the rows hold. Eq 29's QP after it, in the
// finish stage, then projects only what the Newton tolerances left.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

template <class T, int D>
void EolSimulation<T, D>::implicit_contact() {
  implicit_contact_ = ImplicitContactStats{};
  if (scene_.solver.eol.contact != EolSolverDesc::Contact::surface) return;
  move_planes(planes_, time_);  // as finish_step places them, at the step's start
  if (!bodies_.empty()) place_bodies(bodies_, D, time_, body_poses_);
  const std::vector<char> meeting = meeting_objects();
  const bool planes = !planes_.empty() || !body_poses_.empty();
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    if ((!meeting.empty() && meeting[k]) || !planes || !may_touch_planes(objects_[k])) continue;
    plane_rows(objects_[k]);
    constrained_solve({{&objects_[k].grid.mass, &objects_[k].u, 0}}, {&objects_[k]});
  }
  if (meeting.empty()) return;
  const std::vector<ObjectVelocities<T, D>> views = object_rows(meeting);
  std::vector<EolObject<T, D>*> group;
  for (std::size_t k = 0; k < objects_.size(); ++k)
    if (meeting[k]) group.push_back(&objects_[k]);
  constrained_solve(views, group);
}

// The rows in contact_rows_ (nodes numbered as in views) held by the objects' backward Euler
// solves, each already minimised without them.
template <class T, int D>
void EolSimulation<T, D>::constrained_solve(const std::vector<ObjectVelocities<T, D>>& views,
                                            const std::vector<EolObject<T, D>*>& group) {
  const ContactRows<T, D>& J = contact_rows_;
  const int m = int(J.rows());
  if (m == 0) return;
  // Each entry's object and node; the rows' scale Σ|j| times the fastest node's speed.
  const std::size_t entries = J.row.size();
  std::vector<std::uint32_t> owner(entries), local(entries);
  std::vector<double> scale(std::size_t(m), 0.0);
  double speed = 0;
  for (const EolObject<T, D>* o : group)
    for (std::size_t i = 0; i < o->grid.size(); ++i)
      if (o->grid.mass[i] > T(0)) speed = std::max(speed, double(o->u[i].norm()));
  for (std::size_t e = 0; e < entries; ++e) {
    std::size_t k = views.size() - 1;
    while (views[k].node_offset > J.node[e]) --k;
    owner[e] = std::uint32_t(k);
    local[e] = J.node[e] - views[k].node_offset;
    scale[J.row[e]] += double(J.coeff[e].norm());
  }
  auto moves = [&](std::size_t e) { return group[owner[e]]->grid.mass[local[e]] > T(0); };
  // b = J u − r at the solves' velocities (a node without mass keeps its extrapolated u).
  std::vector<double> b(static_cast<std::size_t>(m));
  auto rates = [&]() {
    for (int s = 0; s < m; ++s)
      b[std::size_t(s)] = std::size_t(s) < J.rate.size() ? -double(J.rate[std::size_t(s)]) : 0.0;
    for (std::size_t e = 0; e < entries; ++e) {
      const EolObject<T, D>& o = *group[owner[e]];
      const Vec<T, D> u = moves(e) ? o.implicit.velocity(local[e]) : o.u[local[e]];
      b[J.row[e]] += double(J.coeff[e].dot(u));
    }
  };
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(m);
  auto violation = [&]() {  // the largest, relative to each row's scale
    double worst = 0;
    for (int s = 0; s < m; ++s) {
      const double w = b[std::size_t(s)];
      const bool on = J.bilateral[std::size_t(s)] || lambda[s] > 0;
      const double v = on ? std::abs(w) : std::max(w, 0.0);
      worst = std::max(worst, v / std::max(scale[std::size_t(s)] * speed, 1e-300));
    }
    return worst;
  };
  Eigen::MatrixXd A(m, m);
  std::vector<Vec<T, D>> rhs, response, impulse;
  ImplicitContactStats st;
  st.rows = m;
  for (;; ++st.iterations) {
    rates();
    st.violation = violation();
    if (st.iterations == 0) st.first_violation = st.violation;
    if (st.violation <= kImplicitContactTolerance || st.iterations >= kImplicitContactIterations)
      break;
    // A = J R H⁻¹ Rᵀ Jᵀ, object by object (their H are independent), one CG solve per row.
    A.setZero();
    for (std::size_t k = 0; k < group.size(); ++k) {
      EolObject<T, D>& o = *group[k];
      o.implicit.hessian_here();
      for (int s = 0; s < m; ++s) {
        rhs.assign(o.grid.size(), Vec<T, D>::Zero());
        bool any = false;
        for (std::size_t e = 0; e < entries; ++e)
          if (owner[e] == k && int(J.row[e]) == s && moves(e)) {
            rhs[local[e]] += J.coeff[e];
            any = true;
          }
        if (!any) continue;
        st.cg_iterations += o.implicit.inverse_apply(rhs, response, 1e-6, 1000);
        for (std::size_t e = 0; e < entries; ++e)
          if (owner[e] == k && moves(e))
            A(J.row[e], s) += double(J.coeff[e].dot(response[local[e]]));
      }
    }
    A = (0.5 * (A + A.transpose())).eval();
    const Eigen::VectorXd shifted = Eigen::Map<const Eigen::VectorXd>(b.data(), m) + A * lambda;
    ContactSolveStats dual;
    const Eigen::VectorXd next = contact_solver_.solve_dual(
        A, std::vector<double>(shifted.data(), shifted.data() + m), J.bilateral, dual);
    if (!next.allFinite()) break;
    lambda = next;
    // The impulse −Jᵀλ on each object, and its backward Euler solve again from its last w.
    for (std::size_t k = 0; k < group.size(); ++k) {
      EolObject<T, D>& o = *group[k];
      impulse.assign(o.grid.size(), Vec<T, D>::Zero());
      for (std::size_t e = 0; e < entries; ++e)
        if (owner[e] == k && moves(e)) impulse[local[e]] += T(lambda[J.row[e]]) * J.coeff[e];
      o.implicit.push(impulse);
      const NewtonCgReport r = o.implicit.minimise();
      implicit_report_.newton_iterations += r.newton_iterations;
      implicit_report_.cg_iterations += r.cg_iterations;
    }
  }
  implicit_report_.cg_iterations += st.cg_iterations;
  implicit_contact_.merge(st);
}

}  // namespace apiclab::eol
