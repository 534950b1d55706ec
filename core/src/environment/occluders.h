#pragma once
// Private to core/src/environment: the conservative "can anything block this side's rays at
// all" tests of the loads, on bounding spheres [m] (with the rays' lift and float rounding)
// and a sphere tree over the faces (sphere_tree.h). A side none of whose potential blockers
// passes is decided exactly without rays (fully lit, Earth view unobstructed).
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "load_sides.h"
#include "sphere_tree.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec::load_rays {

// True if no point of side t's triangle lies above side s's plane by more than half s's ray
// lift: rays leaving s (lifted by its offset, going away from its plane) can never meet t.
// Adjacent faces of one panel and faces behind s are ruled out so.
inline bool below_plane_of(const Side& s, const Side& t) {
  const double h = 0.5 * s.offset;
  return s.normal.dot(t.a - s.a) <= h && s.normal.dot(t.b - s.a) <= h && s.normal.dot(t.c - s.a) <= h;
}

// For the conservative "can anything block this side's rays" tests: per side, a bounding
// sphere (plus its ray lift and float rounding: Embree works in single precision), and a
// sphere tree over the faces that could block (each face once, whichever side). A face can
// block side s in some direction only if it is not below s's plane (below_plane_of).
// Direction-independent: built once per run.
struct Occluders {
  std::vector<Eigen::Vector3d> centre;
  std::vector<double> radius;  // < 0 for sides without area
  std::vector<int> face;       // per side: its face
  blockers::SphereTree tree;   // over one side per face
};

// Bounding sphere of a side's ray origins (its triangle lifted by up to its offset, with room
// for rounding): centre `c`, returns the radius [m].
inline double side_bounding_sphere(const Side& g, Eigen::Vector3d& c) {
  c = (g.a + g.b + g.c) / 3.0;
  return std::max({(g.a - c).norm(), (g.b - c).norm(), (g.c - c).norm()}) + 2.0 * g.offset +
         1e-6 * (c.cwiseAbs().maxCoeff() + g.offset) + 1e-9;
}

//! The bounding spheres of `geo`'s sides and the sphere tree over one side per face.
Occluders occluders(const std::vector<Side>& geo, const SurfaceSides& sides);

// True if some potential blocker t of side s (another face, not below s's plane) passes
// `meets(centre, reach)` with reach = radius(s) + radius(t); `meets` must be monotone in reach
// (a bigger sphere passes whenever a smaller one inside it does).
template <class Meets>
bool any_blocker(const std::vector<Side>& geo, const Occluders& occ, int s, Meets&& meets) {
  const Side& g = geo[s];
  const double h = 0.5 * g.offset;  // as below_plane_of
  const double slack = 1e-9 * (g.a.cwiseAbs().maxCoeff() + 1.0);
  return blockers::any_member(
      occ.tree,
      [&](const blockers::SphereTree::Node& n) {
        return blockers::height_above_plane(n, g.normal, g.a) > h - slack && meets(n.centre, occ.radius[s] + n.radius);
      },
      [&](int t) {
        return occ.face[t] != occ.face[s] && !below_plane_of(g, geo[t]) && meets(occ.centre[t], occ.radius[s] + occ.radius[t]);
      });
}

}  // namespace thermodec::load_rays
