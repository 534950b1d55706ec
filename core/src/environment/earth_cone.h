#pragma once
// Private to core/src/environment: the Earth cone rays of each face side (Earth fixed in body
// axes, e.g. nadir pointing) and what they give: F_side->Earth with the share the spacecraft
// blocks, and per kept ray its weight and the Earth normal at its hit (albedo lighting).
#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

#include "load_sides.h"
#include "occluders.h"
#include "ray_records.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::load_rays {

// Earth rays of each side. Directions are drawn uniformly (stratified) inside the cone the
// Earth subtends, not over the hemisphere: every ray then lands on the Earth, the integrand
// (cos theta x visibility x albedo lighting) is smooth wherever the spacecraft does not block
// the view, and the estimate of an unobstructed side is nearly exact. Each ray keeps its
// weight Omega_cap / (pi N) max(0, n . w) (its share of F_side->Earth) and the Earth normal
// at its hit point (for the albedo lighting at every time step).
struct EarthHits {
  std::vector<std::vector<std::pair<float, Eigen::Vector3f>>> rays;  // per side: (weight, normal)
  Eigen::VectorXd view_factor;                                        // per side: sum of weights
  // per side: binomial relative standard error of view_factor, sqrt((1 - p) / (p N)) for an
  // unblocked share p of N rays (0 for unobstructed or fully blocked sides)
  Eigen::VectorXd relative_error;
  // per side: 1 if every ray it traced had its outcome read from the reference record (none
  // traced again): its rays, weights and normals are then the reference's.
  std::vector<char> replayed;
  // The same, flattened for the per-step albedo sums: columns (nx, ny, nz) and weights, side s
  // owning [begin[s], begin[s + 1]).
  Eigen::Matrix<float, Eigen::Dynamic, 3> normals;
  Eigen::VectorXf weights;
  std::vector<int> begin;

  //! Fills the flat arrays from `rays`, then moves `rays` into `keep_rays` (a reference run's
  //! LoadSamples::earth), or frees them.
  void flatten(std::vector<std::vector<std::pair<float, Eigen::Vector3f>>>* keep_rays = nullptr) {
    begin.assign(rays.size() + 1, 0);
    for (size_t s = 0; s < rays.size(); ++s) begin[s + 1] = begin[s] + static_cast<int>(rays[s].size());
    normals.resize(begin.back(), 3);
    weights.resize(begin.back());
    for (size_t s = 0; s < rays.size(); ++s)
      for (size_t k = 0; k < rays[s].size(); ++k) {
        weights[begin[s] + k] = rays[s][k].first;
        normals.row(begin[s] + k) = rays[s][k].second.transpose();
      }
    if (keep_rays) *keep_rays = std::move(rays);
    rays = {};
  }
  bool empty() const { return begin.empty(); }
};

//! Which sides may have their view of the Earth (unit direction `earth_dir`, angular radius
//! asin(sin_half)) blocked at all (conservative; only the sides flagged in `todo`, all if null).
std::vector<char> may_be_blocked_from_earth(const std::vector<Side>& geo, const Occluders& occ,
                                            const Eigen::Vector3d& earth_dir, double sin_half,
                                            const std::vector<char>* todo);

// A trial's shortcut for a side whose every ray kept its reference outcome (the common case:
// on the sample, 60 % of the Earth rays a trial generated were on such sides): only the rays
// whose direction cell can reach the changed region are generated and tested; if all are clear
// the side is replayed from the reference (view factor, error, kept rays) without generating
// the others. Otherwise it is traced as usual, so results are the same bit for bit.
struct EarthReplay {
  const LoadSamples* ref = nullptr;
  bool need_rays = false;  // copy the reference's kept rays of replayed sides (lighting sums)
  std::atomic<int>* replayed_sides = nullptr;  // counts the sides replayed so
};

//! Earth cone rays of every side (see EarthHits) for a central body of radius `radius_m` [m] with
//! its centre at earth_dir_in * distance_m [m] (body axes); `side_rays` = #sides rays for a side whose view is partly blocked (the pilot decides).
EarthHits earth_hits(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                     const Eigen::Vector3d& earth_dir_in, double distance_m, double radius_m, const Eigen::VectorXi& side_rays,
                     int pilot_rays, std::uint64_t seed, const tracing::SobolTable& sobol,
                     const std::vector<char>& may_be_blocked, const PassContext& pass,
                     const std::vector<char>* todo = nullptr, bool flatten = true, const EarthReplay& replay = {},
                     const Occluders* occ = nullptr);

// Origins of a side's rasterised Earth view (earth_raster.h) for a side of `rays` Earth rays:
// one per kRaysPerRasterOrigin rays, a power of two when `rays` is, at least 16.
constexpr int kRaysPerRasterOrigin = 64;
inline int raster_origins(int rays) { return std::max(std::min(rays, 16), rays / kRaysPerRasterOrigin); }

}  // namespace thermodec::load_rays
