#pragma once
// Private to core/src/environment: the Earth rays of attitudes in which the Earth moves in body
// axes (sun-pointing, inertial): cosine-weighted hemisphere rays traced once per side, the
// escaping ones intersected with the Earth's cone at every step.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "load_sides.h"
#include "ray_records.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::load_rays {

// For attitudes in which the Earth moves in body axes (sun-pointing, inertial), tracing Earth
// rays at every step would cost steps x the nadir case. Instead each side traces once a set of
// cosine-weighted hemisphere rays and keeps the directions that escape the spacecraft; at each
// step, the escaping directions that point into the Earth's cone are its Earth hits
// (F = hits / N). The spacecraft is treated as a point against the Earth distance (metres
// against thousands of kilometres). Noisier than the cone sampling at equal ray counts (the
// cone edge is a discontinuity of the integrand), but independent of the step count.
struct EscapingRays {
  Eigen::Matrix<float, Eigen::Dynamic, 3> directions;  // all sides, side s owning [begin[s], begin[s+1])
  std::vector<int> begin;
  Eigen::VectorXi rays;  // per side: rays traced (escaping or not)
};

//! Per side (only those flagged in `todo`, all if null): the directions of its `rays[s]`
//! hemisphere rays that escape the spacecraft.
std::vector<std::vector<Eigen::Vector3f>> escaping_directions(const RayScene& scene, const std::vector<Side>& geo,
                                                             const SurfaceSides& sides, const Eigen::VectorXi& rays, std::uint64_t seed,
                                                             const tracing::SobolTable& sobol, const PassContext& pass,
                                                             const std::vector<char>* todo);

//! The escaping directions of all sides in one matrix (EscapingRays).
EscapingRays pack_escaping(const std::vector<std::vector<Eigen::Vector3f>>& per_side, const Eigen::VectorXi& rays);

// Per side, at one step: F_side->Earth and sum over Earth hits of w max(0, n_E . sun).
// radius_m: the central body's radius [m].
void earth_view_from_escaping(const EscapingRays& esc, const Eigen::Vector3d& earth_dir_in, double distance_m, double radius_m,
                              const Eigen::Vector3d& sun, Eigen::VectorXd& view_factor, Eigen::VectorXd& lit_sum);

}  // namespace thermodec::load_rays
