// Bounding spheres and the blocker tree of the conservative blocking tests (occluders.h).
#include "occluders.h"

namespace thermodec::load_rays {

Occluders occluders(const std::vector<Side>& geo, const SurfaceSides& sides) {
  const int ns = sides.size();
  Occluders o;
  o.centre.assign(ns, Eigen::Vector3d::Zero());
  o.radius.assign(ns, -1.0);
  o.face.assign(sides.face.data(), sides.face.data() + ns);
  std::vector<int> blockers;  // one side per face
  for (int s = 0; s < ns; ++s) {
    const Side& g = geo[s];
    if (g.area <= 0.0) continue;
    o.radius[s] = side_bounding_sphere(g, o.centre[s]);
    const int f = sides.face[s];
    if (sides.front_side[f] < 0 || sides.front_side[f] == s) blockers.push_back(s);
  }
  o.tree = blockers::sphere_tree(blockers, o.centre, o.radius, [&](int t, int k) -> const Eigen::Vector3d& {
    return k == 0 ? geo[t].a : k == 1 ? geo[t].b : geo[t].c;
  });
  return o;
}

}  // namespace thermodec::load_rays
