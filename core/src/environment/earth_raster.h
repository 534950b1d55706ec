#pragma once
// Private to core/src/environment: the Earth view of a face side (Earth fixed in body axes) by
// rasterising its blockers over a fixed grid of directions in the Earth's cone, from sample
// origins on the side. Each origin resolves every direction of the cone at once (a coverage
// mask of the blockers' gnomonic projections), so the Monte Carlo part is a 2-D integral over
// the side of a continuous function (the blocked share seen from one point), not the 4-D
// visibility indicator that single rays sample.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "load_sides.h"
#include "occluders.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::load_rays {

// True if a sphere (centre, reach) [m] may meet a ray leaving the sphere around `from`
// inside the Earth's cone (unit axis `earth_dir`, half-angle with sine sin_half, cosine
// cos_half) and in front of the plane with unit normal `normal` (conservative).
inline bool may_meet_earth_cone(const Eigen::Vector3d& from, const Eigen::Vector3d& normal, const Eigen::Vector3d& earth_dir,
                                double sin_half, double cos_half, const Eigen::Vector3d& centre, double reach) {
  const Eigen::Vector3d v = centre - from;
  if (v.dot(normal) < -reach) return false;  // wholly behind the side
  const double dist2 = v.squaredNorm();
  if (dist2 <= reach * reach) return true;
  // angle(v, earth) <= half + asin(reach / dist), compared through cosines (both angles
  // in [0, pi], cos decreasing there): cos(half + beta) = cos_half cos_beta - sin_half sin_beta.
  const double dist = std::sqrt(dist2), sin_b = reach / dist, cos_b = std::sqrt(1.0 - sin_b * sin_b);
  return v.dot(earth_dir) / dist >= cos_half * cos_b - sin_half * sin_b - 1e-6;  // (float ray directions)
}

// The Earth's cone as a grid of kN x kN directions: pixel (i, j) is the direction
// e + X t + Y u (normalised), (X, Y) its centre on the gnomonic plane at unit distance along e,
// X, Y in [-T, T], T = tan(half-angle); only pixels whose centre lies in the disk of radius T
// (the cone) count. Triangles project to triangles on that plane, so a blocker's coverage is
// a span per row (one 64-bit word).
struct EarthGrid {
  static constexpr int kN = 64;
  Eigen::Vector3d e, t, u;
  double tan_half = 0.0, step = 0.0;         // T and the pixel pitch 2T / kN
  std::vector<Eigen::Vector3d> dir;          // per pixel: unit direction (body axes)
  std::vector<double> solid_angle_over_pi;   // per pixel: its solid angle [sr] / pi, 0 outside the cone
  std::vector<Eigen::Vector3f> earth_normal; // per pixel: the Earth's normal where the direction meets it
  std::array<std::uint64_t, kN> in_cone{};   // per row: the pixels inside the cone
  //! Grid for an Earth of radius `radius_m` [m] whose centre lies at distance_m [m] along
  //! the unit `earth_dir`, with the azimuth frame (t, u).
  EarthGrid(const Eigen::Vector3d& earth_dir, const Eigen::Vector3d& t, const Eigen::Vector3d& u, double distance_m,
            double radius_m);
};

// Per-thread scratch of earth_view_by_raster.
struct RasterScratch {
  std::vector<int> blockers;
  std::vector<double> weight;               // per pixel: dOmega / pi max(0, n . w)
  std::vector<std::uint32_t> blocked_count;  // per pixel: origins that see it blocked
  std::array<std::uint64_t, EarthGrid::kN> open{}, cover{};
};

// What earth_view_by_raster gives for one side.
struct RasterView {
  double view_factor = 0.0;     // F_side->Earth with the blocked share
  double relative_error = 0.0;  // estimated standard error of the unblocked share, relative
  int origins = 0;              // origins rasterised (0: nothing can block the side)
  bool by_rays = false;         // not computed: rasterising would cost more than `rays` rays
};

// What one Earth ray costs in rasterised triangles (projection, clipping, row spans against
// an Embree occlusion query), for the choice between the two: measured ~150 ns a triangle on
// the sample and NPP_16 (median over sides, loaded machine).
constexpr double kRasterTrianglesPerRay = 4.0;

//! Side s's Earth view: the closed form `f_open` (unobstructed view factor) times the unblocked
//! share of the grid's cos-weighted directions, averaged over `origins` Owen-scrambled Sobol
//! points on the side (scramble seeds `sd`, points `sobol`, at least `origins` of them); only
//! the faces that may meet the side's Earth cone (`may_be_blocked` false: none, no origins)
//! are rasterised. Appends to `keep` one (weight, Earth normal) per visible pixel, weights
//! summing to the view factor (the albedo lighting sums). If #blockers x origins exceeds
//! kRasterTrianglesPerRay x `rays` (large CAD meshes), returns by_rays set and nothing else.
RasterView earth_view_by_raster(const EarthGrid& grid, const std::vector<Side>& geo, const Occluders& occ, int s,
                                bool may_be_blocked, double sin_half, double f_open, int origins, int rays,
                                const std::array<std::uint32_t, 4>& sd, const tracing::SobolTable& sobol,
                                RasterScratch& x, std::vector<std::pair<float, Eigen::Vector3f>>& keep);

}  // namespace thermodec::load_rays
