// Which sides' rays a trial's change can reach (change_reach.h).
#include "change_reach.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "thermodec/rays/ray_scene.h"

namespace thermodec::load_rays {

namespace {

double bounding_sphere(const Side& g, Eigen::Vector3d& c) {
  c = (g.a + g.b + g.c) / 3.0;
  return std::max({(g.a - c).norm(), (g.b - c).norm(), (g.c - c).norm()}) + 2.0 * g.offset + 1e-9;
}

// The side's rays all leave forwards (n . d > 0) from within its bounding sphere (centre c,
// radius rho), so they stay in the half-space n . x >= n . c - rho: a region wholly behind it
// is out of reach.
bool region_behind(const Side& g, const Eigen::Vector3d& c, double rho, const Eigen::AlignedBox3d& box) {
  const Eigen::Vector3d& n = g.normal;
  const double support = n.dot(box.center()) + n.cwiseAbs().dot(0.5 * box.diagonal());
  return support < n.dot(c) - rho - 1e-9 * (1.0 + box.diagonal().norm() + c.norm());
}

}  // namespace

ChangeReach::ChangeReach(const std::vector<Side>& geo_in, const LoadReuse* reuse) : geo(geo_in) {
  if (!reuse || !reuse->reference) return;
  const int ns = static_cast<int>(geo.size());
  side_centre.resize(ns);
  side_radius.resize(ns);
  behind.assign(ns, 0);
  for (int s = 0; s < ns; ++s) {
    side_radius[s] = bounding_sphere(geo[s], side_centre[s]);
    if (!reuse->changed_region.isEmpty())
      behind[s] = region_behind(geo[s], side_centre[s], side_radius[s], reuse->changed_region);
  }
  changed_region = reuse->changed_region;
  if (!reuse->changed_region.isEmpty()) {
    change_centre = reuse->changed_region.center();
    change_radius = 0.5 * reuse->changed_region.diagonal().norm();
  } else {
    change_radius = -1.0;  // nothing changed: everything present is reusable
  }
  if (reuse->changed_faces) {
    const Mesh& m = reuse->changed_faces->mesh();
    std::vector<int> members(m.num_faces());
    changed_centre.resize(m.num_faces());
    changed_radius.resize(m.num_faces());
    auto corner = [&](int f, int k) -> Eigen::Vector3d { return m.V.row(m.F(f, k)).transpose(); };
    for (int f = 0; f < m.num_faces(); ++f) {
      members[f] = f;
      changed_centre[f] = (corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3.0;
      double r = 0.0;
      for (int k = 0; k < 3; ++k) r = std::max(r, (corner(f, k) - changed_centre[f]).norm());
      // float rounding of the traced coordinates, as the box's margin
      changed_radius[f] = r + 1e-6 * (changed_centre[f].cwiseAbs().maxCoeff() + r) + 1e-9;
    }
    std::vector<std::array<Eigen::Vector3d, 3>> corners(m.num_faces());
    for (int f = 0; f < m.num_faces(); ++f) corners[f] = {corner(f, 0), corner(f, 1), corner(f, 2)};
    changed_tree = blockers::sphere_tree(members, changed_centre, changed_radius,
                                         [&](int f, int k) -> const Eigen::Vector3d& { return corners[f][k]; });
  }
}

bool ChangeReach::clear_along(int s, const Eigen::Vector3d& d) const {  // half-line family c + t d
  if (change_radius < 0.0 || change_behind(s)) return true;
  if (!changed_tree.nodes.empty() &&
      !changed_face_meets(s, [&](const Eigen::Vector3d& v, double reach) {
        const double along = v.dot(d);
        return along >= -reach && v.squaredNorm() - along * along <= reach * reach * (1.0 + 1e-9);
      }))
    return true;
  Eigen::Vector3d c;
  const double rho = side_sphere(s, c);
  const Eigen::Vector3d bc = change_centre - c;
  const double t = std::max(0.0, bc.dot(d));
  if ((bc - t * d).norm() > rho + change_radius) return true;
  // Tighter for flat or long regions: the swept sphere {c + t d + r, |r| <= rho} meets the
  // region only if the half-line from c meets the region grown by rho (slab test).
  const Eigen::AlignedBox3d& box = changed_region;
  const double grow = rho + 1e-9 * (1.0 + box.diagonal().norm());
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double lo = box.min()[k] - grow, hi = box.max()[k] + grow;
    if (d[k] == 0.0) {
      if (c[k] < lo || c[k] > hi) return true;
      continue;
    }
    double ta = (lo - c[k]) / d[k], tb = (hi - c[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return true;
  }
  // Exact for the side itself: its rays leave the triangle (lifted by up to its offset)
  // along d, i.e. they fill a prism; it misses the region if some axis separates them
  // (separating axes of a prism along d and a box: the prism's side normals e x d, the
  // box's axes x d, and d itself for a region behind). On the sample, 8 of every 14 sides
  // the sphere tests kept had no ray entering the region.
  const Side& g = geo[s];
  const Eigen::Vector3d lift = g.normal * g.offset;
  const std::array<Eigen::Vector3d, 6> corner = {g.a, g.b, g.c, g.a + lift, g.b + lift, g.c + lift};
  const Eigen::Vector3d half = 0.5 * box.sizes() + Eigen::Vector3d::Constant(1e-5 * (1.0 + box.diagonal().norm() + c.norm() + rho));
  auto separates = [&](const Eigen::Vector3d& axis, bool half_line) {
    const double len = axis.norm();
    if (!(len > 1e-9)) return false;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& v : corner) {
      lo = std::min(lo, v.dot(axis));
      hi = std::max(hi, v.dot(axis));
    }
    const double centre = box.center().dot(axis), reach = half.dot(axis.cwiseAbs());
    if (half_line) return centre + reach < lo;  // all of the region behind the prism's start
    return centre + reach < lo || centre - reach > hi;
  };
  if (separates(d, true)) return true;
  const std::array<Eigen::Vector3d, 3> edge = {g.b - g.a, g.c - g.b, g.a - g.c};
  for (const auto& e : edge)
    if (separates(e.cross(d), false)) return true;
  for (int k = 0; k < 3; ++k)
    if (separates(Eigen::Vector3d::Unit(k).cross(d), false)) return true;
  return false;
}

bool ChangeReach::clear_in_cone(int s, const Eigen::Vector3d& axis, double half_angle) const {
  if (change_radius < 0.0 || change_behind(s)) return true;
  if (!changed_tree.nodes.empty() &&
      !changed_face_meets(s, [&](const Eigen::Vector3d& v, double reach) {
        const double dist = v.norm();
        if (dist <= reach) return true;
        const double angle = std::acos(std::clamp(v.dot(axis) / dist, -1.0, 1.0));
        return angle <= half_angle + std::asin(std::min(1.0, reach / dist)) + 1e-9;
      }))
    return true;
  Eigen::Vector3d c;
  const double rho = side_sphere(s, c);
  const Eigen::Vector3d bc = change_centre - c;
  const double dist = bc.norm(), reach = rho + change_radius;
  if (dist <= reach) return false;
  const double angle = std::acos(std::clamp(bc.dot(axis) / dist, -1.0, 1.0));
  return angle > half_angle + std::asin(std::min(1.0, reach / dist)) + 1e-9;
}

bool ChangeReach::clear_in_front(int s) const {
  if (change_radius < 0.0 || change_behind(s)) return true;
  Eigen::Vector3d c;
  const double rho = side_sphere(s, c);
  return (change_centre - c).dot(geo[s].normal) < -(rho + change_radius);
}

}  // namespace thermodec::load_rays
