#pragma once
// Private to core/src/environment: which face sides' ray families a trial's change can reach
// at all (LoadReuse::changed_region, optionally LoadReuse::changed_faces), by conservative
// sphere, slab and separating-axis tests [m]. A side whose rays cannot reach the change is
// reused whole from the reference run (its shadow fractions, its Earth hits); the others go
// to the per-ray records (ray_records.h). A wrong "clear" would change results, so every test
// errs on "may reach" (margins for float rounding included).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "load_sides.h"
#include "sphere_tree.h"
#include "thermodec/environment/external_loads.h"

namespace thermodec::load_rays {

struct ChangeReach {
  const std::vector<Side>& geo;
  Eigen::AlignedBox3d changed_region;  // the trial's changed region [m, body axes]
  // Its bounding sphere; radius < 0: nothing changed, every side is clear.
  Eigen::Vector3d change_centre = Eigen::Vector3d::Zero();
  double change_radius = 0.0;
  // The changed faces themselves (LoadReuse::changed_faces), if given: a sphere tree over them,
  // so that a side is tested against the changed faces, not against their bounding box (a
  // decimated CAD part spread along the craft has a box that covers most of it).
  std::vector<Eigen::Vector3d> changed_centre;
  std::vector<double> changed_radius;
  blockers::SphereTree changed_tree;
  // Per side, computed once for every pass of the trial: its bounding sphere (side_sphere) and
  // whether the change lies behind it (change_behind).
  std::vector<Eigen::Vector3d> side_centre;
  std::vector<double> side_radius;
  std::vector<char> behind;

  //! For a trial with reuse->reference set: the change of `reuse` seen from the sides `geo`.
  ChangeReach(const std::vector<Side>& geo, const LoadReuse* reuse);

  //! Bounding sphere of side s (plus its ray lift): centre `c`, returns the radius [m].
  double side_sphere(int s, Eigen::Vector3d& c) const {
    c = side_centre[s];
    return side_radius[s];
  }
  //! The side's rays all leave forwards (n . d > 0) from within its bounding sphere, so they
  //! stay in the half-space n . x >= n . c - rho: a region wholly behind it is out of reach.
  bool change_behind(int s) const { return behind[s] != 0; }
  //! The rays of side s along the unit direction d (the sun's) cannot reach the change.
  bool clear_along(int s, const Eigen::Vector3d& d) const;
  //! The rays of side s inside the cone (unit axis, half-angle [rad]) cannot reach the change.
  bool clear_in_cone(int s, const Eigen::Vector3d& axis, double half_angle) const;
  //! No ray of side s's hemisphere can reach the change.
  bool clear_in_front(int s) const;

  // Some changed face's sphere meets the side's sphere swept along d (`swept`) or the cone
  // it sees the Earth through (`cone`); conservative, as the box tests.
  template <class Meets>
  bool changed_face_meets(int s, Meets&& meets) const {
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    return blockers::any_member(
        changed_tree, [&](const blockers::SphereTree::Node& n) { return meets(n.centre - c, rho + n.radius); },
        [&](int f) { return meets(changed_centre[f] - c, rho + changed_radius[f]); });
  }
};

}  // namespace thermodec::load_rays
