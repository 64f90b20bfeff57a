// One contact QP for every object (Fan et al. 2013, eq 29): M̃ is the objects' lumped masses
// side by side (block diagonal, so still diagonal), J has a column block per object and its
// rows touch two objects' nodes (object_contact.hpp) or one object's and a plane's
// (surface_contact.hpp). Only the nodes some row touches enter the solve: ContactSolver
// (contact_qp.hpp) runs on them, renumbered, and each object's velocities take its share of
// u = u* − M̃⁻¹Jᵀλ.
#pragma once
#include <algorithm>
#include <vector>

#include "sim/eol/contact/contact_qp.hpp"
#include "sim/eol/contact/object_contact_3d.hpp"

namespace apiclab::eol {

// One object's lumped masses and world node velocities (u* in, u out), and its first node in
// J's numbering.
template <class T, int D>
struct ObjectVelocities {
  const std::vector<T>* mass = nullptr;
  std::vector<Vec<T, D>>* u = nullptr;
  std::uint32_t node_offset = 0;
};

// Appends one object's rows against the planes (eq 28 with the plane's normal) to `rows`, its
// nodes renumbered by the object's offset.
template <class T, int D>
void append_plane_rows(const ContactObject<T, D>& o,
                       const std::vector<PlaneConstraint<T, D>>& planes, T cell,
                       ContactRows<T, D>& scratch, ContactRows<T, D>& rows) {
  scratch.clear();
  assemble_surface_rows(*o.grid, *o.y, *o.simplex, o.R, o.p, planes, cell, scratch);
  const auto first = std::uint32_t(rows.rows());
  for (std::size_t e = 0; e < scratch.row.size(); ++e) {
    rows.row.push_back(first + scratch.row[e]);
    rows.node.push_back(o.node_offset + scratch.node[e]);
    rows.coeff.push_back(scratch.coeff[e]);
  }
  if (!scratch.rate.empty()) {  // a moving plane's rates, after the earlier rows' zeros
    rows.rate.resize(first, T(0));
    rows.rate.insert(rows.rate.end(), scratch.rate.begin(), scratch.rate.end());
  }
  rows.bilateral.insert(rows.bilateral.end(), scratch.bilateral.begin(), scratch.bilateral.end());
  rows.key.insert(rows.key.end(), scratch.key.begin(), scratch.key.end());
}

template <class T, int D>
class GlobalContactSolver {
 public:
  // Solves eq 29 over all objects; `objects` in order of node_offset, J in their numbering.
  ContactSolveStats solve(const ContactRows<T, D>& J,
                          const std::vector<ObjectVelocities<T, D>>& objects) {
    nodes_.assign(J.node.begin(), J.node.end());
    std::sort(nodes_.begin(), nodes_.end());
    nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
    local_.clear();
    local_.row = J.row;
    local_.coeff = J.coeff;
    local_.bilateral = J.bilateral;
    local_.rate = J.rate;
    local_.key = J.key;
    local_.node.resize(J.node.size());
    for (std::size_t e = 0; e < J.node.size(); ++e)
      local_.node[e] =
          std::uint32_t(std::lower_bound(nodes_.begin(), nodes_.end(), J.node[e]) - nodes_.begin());
    mass_.resize(nodes_.size());
    u_.resize(nodes_.size());
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
      const auto& [o, i] = locate(objects, nodes_[k]);
      mass_[k] = (*o.mass)[i];
      u_[k] = (*o.u)[i];
    }
    const ContactSolveStats st = solver_.solve(local_, mass_, u_);
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
      const auto& [o, i] = locate(objects, nodes_[k]);
      (*o.u)[i] = u_[k];
    }
    return st;
  }
  const Eigen::VectorXd& multipliers() const { return solver_.multipliers(); }

 private:
  // The object holding global node g, and g's index in it.
  static std::pair<const ObjectVelocities<T, D>&, std::size_t> locate(
      const std::vector<ObjectVelocities<T, D>>& objects, std::uint32_t g) {
    const auto it = std::upper_bound(
        objects.begin(), objects.end(), g,
        [](std::uint32_t v, const ObjectVelocities<T, D>& o) { return v < o.node_offset; });
    const ObjectVelocities<T, D>& o = *(it - 1);
    return {o, std::size_t(g - o.node_offset)};
  }

  std::vector<std::uint32_t> nodes_;
  ContactRows<T, D> local_;
  std::vector<T> mass_;
  std::vector<Vec<T, D>> u_;
  ContactSolver<T, D> solver_;
};

}  // namespace apiclab::eol
