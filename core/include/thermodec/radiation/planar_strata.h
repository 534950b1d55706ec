#pragma once
//! Control variates for view-factor rows: the directions from a side towards a flat node,
//! whose share of the side's cosine-weighted hemisphere has a closed form (docs/radiation.md,
//! "Planar control variates").
//!
//! A side's Monte Carlo row F(s, .) counts where its rays land. Whether a ray crosses the
//! convex hull P of a planar node is an indicator c_P whose exact mean is the unoccluded view
//! factor U_sP (polygon_view_factor.h); whether it crosses every hull of a set T is the
//! product c_T, whose mean U_sT has the same closed form over the hulls' common cone. The
//! regression estimator F(s, t) = mean(h_t) - beta_t . (mean(c) - U) over every c_T, beta_t
//! fitted on the side's own rays, is a weighted count: every ray weighs
//! (1 + b . m - sum_{T within its crossings} b_T) / R, b = cov(c)^+ (m - U), m = mean(c). With
//! every product among the controls this is post-stratification by the set of hulls crossed
//! (p_mask / n_mask per ray). The weights sum to 1 (rows stay closed). A node nothing hides
//! from s is then seen exactly, and so is one hidden only behind other hulls; one hidden by
//! something else keeps only the variance of its hidden share.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "thermodec/mesh/mesh.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec {

//! A convex polygon whose crossing by a ray is a control: the hull of a flat node (all its
//! faces in one plane, normals parallel, every vertex within 1e-9 of the mesh's extent of it,
//! covering >= 90 % of the hull), a control for the other nodes' sides; or the aperture of a
//! node shaped as a concave cap (a dish: its outline on a plane across its opening, which a
//! ray from its concave side crosses iff it leaves the cap), a control for its own sides.
struct NodeHull {
  int node = -1;
  bool aperture = false;                              //!< an aperture, not a flat node's hull
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  //!< unit normal of the plane
  double offset = 0.0;                               //!< normal . y for y in the plane [m]
  std::vector<Eigen::Vector3d> vertices;              //!< convex hull, in order [m]
  Eigen::Vector3d axis_u, axis_v;                     //!< in-plane frame of `vertices`
  std::vector<Eigen::Vector2d> vertices_uv;           //!< the hull in that frame [m]
  //! Single-precision copies for the per-ray test: normal, offset, frame, and per hull edge
  //! (a_u, a_v, b) with a point (u, v) inside iff a_u u + a_v v >= b for every edge.
  float fnormal[3], foffset, fu[3], fv[3];
  std::vector<std::array<float, 3>> edges;
};

//! The hulls of the flat nodes among 0..num_nodes-1 (the `max_hulls` largest by area), then
//! the apertures of the concave caps.
std::vector<NodeHull> planar_node_hulls(const Mesh& mesh, const SurfaceSides& sides, int num_nodes, int max_hulls = 64);

//! The control hulls of one side: up to kMaxStrataPerSide, by decreasing unoccluded share.
constexpr int kMaxStrataPerSide = 4;
struct SideStrata {
  int count = 0;
  std::array<int, kMaxStrataPerSide> hull{};       //!< index into the hulls
  std::array<double, kMaxStrataPerSide> share{};   //!< U_sP [-]
  //! Per set T of the side's hulls (bit k: hull[k]), the share of its directions that cross
  //! every hull of T, U_sT [-] (triangle_to_polygons_view_factor); joint[1 << k] = share[k].
  //! The controls are the products of crossing indicators over every T, so the estimate is
  //! post-stratified by which hulls a ray crosses: a node hidden behind another's hull (the
  //! rays crossing both land on the nearer) is seen as exactly as an unhidden one.
  std::array<double, 1 << kMaxStrataPerSide> joint{};
};

//! The control hulls of each side (#S): the flat hulls of other nodes and the aperture of its
//! own, whose plane does not cut or hold the side, with an unoccluded share U in
//! [min_share, 1 - min_share], the largest kMaxStrataPerSide.
//! Each side is emitted from its lifted triangle (sampling::make_emitter), so the shares are
//! computed there. Deterministic; parallel over sides.
std::vector<SideStrata> side_strata(const Mesh& mesh, const SurfaceSides& sides, const std::vector<NodeHull>& hulls,
                                    double min_share = 1e-3);

//! A side whose row is a regression estimate: its hulls, its rays per stratum mask and, per
//! mask, where those rays landed (side, or -1 for space; fraction of all the side's rays) in
//! side order: what the variance of the estimate needs (aggregate_couplings).
struct ControlledSide {
  SideStrata strata;
  std::vector<double> rays_per_stratum;                          //!< 2^count counts
  std::vector<std::vector<std::pair<int, double>>> hits;         //!< per mask
};

//! Per-ray variance [score^2] of the regression estimate of sum_t F(s, t) score(t) for each
//! column of `score` (#S x C, landing on side t scores score(t, .); escaping scores
//! `space_score`): the plain count's variance less what the crossing indicators explain,
//! Var(score) - cov(c, score)' cov(c)^+ cov(c, score), at least 0. Divide by the side's rays.
Eigen::RowVectorXd controlled_score_variance(const ControlledSide& side,
                                            const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& score,
                                            const Eigen::RowVectorXd& space_score);

//! The stratum of a ray (origin, unit direction, single precision as traced): the bit mask of
//! the side's hulls it crosses at a positive distance (bit k: strata.hull[k]).
int stratum_of_ray(const SideStrata& strata, const std::vector<NodeHull>& hulls, const float* org, const float* dir);

//! The weight of one ray of each stratum (2^count masks) in the regression estimator, from the
//! number of the side's rays in each: (1 + b . m - sum_{k in mask} b_k) / R (see above).
std::vector<double> stratum_weights(const SideStrata& strata, const std::vector<double>& rays_per_stratum);

}  // namespace thermodec
