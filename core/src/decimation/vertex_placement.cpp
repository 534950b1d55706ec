// Where a collapse puts the merged vertex [m]: the Lindstrom-Turk point (volume preservation,
// then volume optimisation, then shape, as a hierarchy of linear constraints), moved to keep
// the node's area (area_neutral_placement); on a contour, the kept end, if the contour stays
// nearly straight there.
#include <algorithm>
#include <cmath>

#include "node_collapse.h"

namespace thermodec::collapse {

bool NodeCollapse::place(Context& c, VVertex* gone, VVertex* kept, bool optimal, const Vec3& pg, const Vec3& pk,
                         double& boundary_cost, bool& straight) {
  auto& star_ = c.star;
  if (optimal) {
    // Lindstrom-Turk placement: volume preservation, then volume optimisation, then shape.
    Constraints k;
    Vec3 nsum = Vec3::Zero();
    double dsum = 0;
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Vec3 g = Vec3::Zero();
    for (VFace* f : star_) {
      const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
      const Vec3 n = (p1 - p0).cross(p2 - p0);
      const double d = n.dot(p0);
      nsum += n;
      dsum += d;
      h += n * n.transpose();
      g += n * d;
    }
    k.add(nsum, dsum);
    k.add_objective(h, g);
    Vec3 centroid = Vec3::Zero();
    int nlink = 0;
    for (VFace* f : star_)
      for (int j = 0; j < 3; ++j) {
        VVertex* v = f->V(j);
        if (v == gone || v == kept) continue;
        centroid += to_eigen(v->cP());
        ++nlink;
      }
    // Shape optimisation: sum |x - p_j|^2 over link vertices -> H = nlink I, g = sum p_j.
    if (nlink > 0) k.add_objective(Eigen::Matrix3d::Identity() * nlink, centroid);
    x_ = k.n == 3 ? k.solve() : 0.5 * (pg + pk);
    if (!x_.allFinite()) return set_refused(CollapseBlock::topology), false;
    if (c.opt.area_neutral_placement) place_area_neutral(c);
  } else {
    x_ = pk;
    if (c.vclass[c.vi(gone)] == kContour) {
      // The contour loses `gone`; it must stay nearly straight there (shape error bound).
      VVertex* w = other_contour_neighbour(c, gone, kept);
      if (w == nullptr) return set_refused(CollapseBlock::frozen_vertices), false;
      if (w == kept) return set_refused(CollapseBlock::topology), false;
      const Vec3 pw = to_eigen(w->cP());
      const Vec3 seg = pw - pk;
      const double len2 = seg.squaredNorm();
      if (!(len2 > 0)) return set_refused(CollapseBlock::topology), false;
      const double t = std::clamp((pg - pk).dot(seg) / len2, 0.0, 1.0);
      const double dev = (pg - (pk + t * seg)).norm();
      if (dev > c.opt.max_contour_deviation * std::sqrt(len2)) {
        // A kink: allowed up to max_kinked_contour_deviation when the nodes on the contour pay
        // for the outline's move (the triangle it sweeps) from their projected-area budget;
        // beyond it under the projected-area cap when that triangle is small against the area
        // each node may move (wide_kink_area_fraction, checked per node in evaluate()).
        if (!(c.opt.projected_area_budget > 0)) return set_refused(CollapseBlock::contour_deviation), false;
        if (dev > c.opt.max_kinked_contour_deviation * std::sqrt(len2)) {
          if (!(c.opt.wide_kink_area_fraction > 0) || c.node_projection_change.empty())
            return set_refused(CollapseBlock::contour_deviation), false;
          wide_kink_ = true;
        }
        kink_m2_ = 0.5 * (pg - pk).cross(pw - pk).norm();
      }
      straight = c.opt.free_exact_contour_collapses && dev <= c.opt.exact_contour_tolerance * std::sqrt(len2);
      // LT boundary preservation: squared swept area of the contour, times a length^2.
      const double swept = 0.5 * (pg - pk).cross(pw - pk).norm();
      boundary_cost = swept * swept * len2;
    }
  }
  return true;
}

int NodeCollapse::corners_after(const VFace* f, const Vec3& x, std::array<Vec3, 3>& q, int& moved_at) const {
  int moved = 0;
  for (int k = 0; k < 3; ++k) {
    q[k] = to_eigen(f->cP(k));
    if (f->cV(k) == pos.cV(0) || f->cV(k) == pos.cV(1)) q[k] = x, moved_at = k, ++moved;
  }
  return moved;
}

void NodeCollapse::place_area_neutral(const Context& c) {
  const auto& star = c.star;
  double area_before = 0;
  for (const VFace* f : star) {
    const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
    area_before += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  if (!(area_before > 0)) return;
  // Area of the surviving star faces with the moved vertex at x [m^2], and its gradient [m]:
  // for a triangle (x, b, c), d area / dx = (b - c) x n / 2 with n its unit normal.
  auto area_at = [&](const Vec3& x, Vec3& grad) {
    double area = 0;
    grad.setZero();
    std::array<Vec3, 3> q;
    for (const VFace* f : star) {
      int j = -1;
      if (corners_after(f, x, q, j) != 1) continue;  // the faces on the collapsed edge disappear
      const Vec3& b = q[(j + 1) % 3];
      const Vec3& d = q[(j + 2) % 3];
      const Vec3 n = (b - x).cross(d - x);
      const double len = n.norm();
      area += 0.5 * len;
      if (len > 0) grad += 0.5 * (b - d).cross(n / len);
    }
    return area;
  };
  const double max_move = 0.1 * std::sqrt(2.0 * area_before / static_cast<double>(star.size()));
  const int node = c.region_node[c.face_region[c.fi(star.front())]];
  const double drift = c.node_area[node] - c.node_area0[node];
  const double targets[2] = {area_before - drift, area_before};  // the second if the first fails
  for (int k = 0; k < (drift != 0.0 ? 2 : 1); ++k) {
    const double target = targets[k];
    Vec3 x = x_, grad;
    bool converged = false;
    for (int it = 0; it < 6 && !converged; ++it) {
      const double residual = target - area_at(x, grad);
      converged = std::abs(residual) <= 1e-12 * area_before;
      const double g2 = grad.squaredNorm();
      if (converged || !(g2 > 0)) break;
      x += (residual / g2) * grad;
      if (!((x - x_).norm() <= max_move)) break;
    }
    if (converged && (x - x_).norm() <= max_move && keeps_closed_volume(c, x)) {
      x_ = x;
      return;
    }
  }
}

bool NodeCollapse::keeps_closed_volume(const Context& c, const Vec3& x) const {
  const int comp = c.face_component[c.fi(c.star.front())];
  if (!c.comp_closed[comp]) return true;
  double delta = 0;  // change of the closed part's volume [m^3]
  std::array<Vec3, 3> q;
  for (const VFace* f : c.star) {
    int j = -1;
    const int moved = corners_after(f, x, q, j);
    const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
    delta -= p0.dot(p1.cross(p2)) / 6.0;
    if (moved == 1) delta += q[0].dot(q[1].cross(q[2])) / 6.0;
  }
  return c.volume_within_bound(comp, delta);
}

}  // namespace thermodec::collapse
