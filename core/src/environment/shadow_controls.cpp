#include "shadow_controls.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "thermodec/radiation/polygon_view_factor.h"
#include "thermodec/radiation/side_strata_of.h"

namespace thermodec::load_rays {
namespace {

using Poly2 = std::vector<Eigen::Vector2d>;

double signed_area(const Poly2& p) {
  double a = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Eigen::Vector2d& u = p[k];
    const Eigen::Vector2d& v = p[(k + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

// p clipped to the convex polygon q (counter-clockwise), Sutherland-Hodgman.
Poly2 clip_to_convex(Poly2 p, const Poly2& q) {
  for (std::size_t e = 0; e < q.size() && p.size() >= 3; ++e) {
    const Eigen::Vector2d a = q[e], b = q[(e + 1) % q.size()];
    const auto inside = [&](const Eigen::Vector2d& x) { return (b - a).x() * (x - a).y() - (b - a).y() * (x - a).x(); };
    Poly2 out;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Eigen::Vector2d& u = p[k];
      const Eigen::Vector2d& v = p[(k + 1) % p.size()];
      const double du = inside(u), dv = inside(v);
      if (du >= 0.0) out.push_back(u);
      if ((du >= 0.0) != (dv >= 0.0)) out.push_back(u + (du / (du - dv)) * (v - u));
    }
    p = std::move(out);
  }
  if (p.size() < 3) p.clear();
  return p;
}

}  // namespace

double shadow_share(const Side& g, const Eigen::Vector3d& toward, const std::vector<std::vector<Eigen::Vector3d>>& ps) {
  const Eigen::Vector3d& n = g.normal;
  const double facing = n.dot(toward);
  if (!(facing > 0.0) || !(g.area > 0.0)) return 0.0;
  const Eigen::Vector3d lift = g.offset * n, a = g.a + lift;
  const Eigen::Vector3d u = (g.b - g.a).normalized(), v = n.cross(u);
  const auto to2 = [&](const Eigen::Vector3d& y) { return Eigen::Vector2d(u.dot(y - a), v.dot(y - a)); };
  Poly2 region{to2(g.a + lift), to2(g.b + lift), to2(g.c + lift)};
  if (signed_area(region) < 0.0) std::reverse(region.begin(), region.end());
  const double whole = std::abs(signed_area(region));
  if (!(whole > 0.0)) return 0.0;
  for (const std::vector<Eigen::Vector3d>& p : ps) {
    // The part in front of the side's plane, projected along -toward onto it.
    const std::vector<Eigen::Vector3d> front = clip_polygon_to_half_space(p, a, n);
    if (front.empty()) return 0.0;
    Poly2 q;
    for (const Eigen::Vector3d& y : front) q.push_back(to2(y - toward * (n.dot(y - a) / facing)));
    if (signed_area(q) < 0.0) std::reverse(q.begin(), q.end());
    if (!(std::abs(signed_area(q)) > 0.0)) return 0.0;  // seen edge-on along the sun
    region = clip_to_convex(std::move(region), q);
    if (region.empty()) return 0.0;
  }
  return std::clamp(std::abs(signed_area(region)) / whole, 0.0, 1.0);
}

SideStrata shadow_strata(const Side& g, int node, const Eigen::Vector3d& toward, const std::vector<NodeHull>& hulls) {
  constexpr double kMin = 1e-3;  // a near-constant indicator explains nothing
  std::vector<std::pair<double, int>> cand;
  for (int k = 0; k < static_cast<int>(hulls.size()); ++k) {
    if ((hulls[k].node == node) != hulls[k].aperture) continue;  // as side_strata
    const double s = shadow_share(g, toward, {hulls[k].vertices});
    if (s >= kMin && s <= 1.0 - kMin) cand.emplace_back(s, k);
  }
  return side_strata_of(cand, hulls, [&](const std::vector<std::vector<Eigen::Vector3d>>& ps) {
    return shadow_share(g, toward, ps);
  });
}

}  // namespace thermodec::load_rays
