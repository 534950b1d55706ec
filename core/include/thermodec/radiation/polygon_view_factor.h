#pragma once
//! Closed-form diffuse view factor from a triangle to a planar convex polygon, with nothing
//! between them (no occlusion).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace thermodec {

//! View factor [-] from the point x with unit normal n to the polygon `p` (vertices in order,
//! either winding), all of it in front of x's tangent plane: Lambert's contour integral,
//! F = |sum_k theta_k n . (r_k x r_k+1) / |r_k x r_k+1|| / (2 pi), r_k = p_k - x, theta_k the
//! angle between r_k and r_k+1 (Howell's catalogue, "point to polygon"). Exact.
double point_to_polygon_view_factor(const Eigen::Vector3d& x, const Eigen::Vector3d& n,
                                    const std::vector<Eigen::Vector3d>& p);

//! The part of polygon `p` on the side of the plane n . (y - a) >= 0 (Sutherland-Hodgman);
//! empty if none of it is.
std::vector<Eigen::Vector3d> clip_polygon_to_half_space(const std::vector<Eigen::Vector3d>& p,
                                                        const Eigen::Vector3d& a, const Eigen::Vector3d& n);

//! View factor [-] from the triangle (a, b, c), emitting along `n` (unit; its front or back
//! normal), to the planar convex polygon `p`, unoccluded: the area mean of
//! point_to_polygon_view_factor over the triangle (`p` clipped to the triangle's front half
//! space first), by a degree-5 Dunavant rule refined adaptively (4 sub-triangles) where one
//! level changes the result by more than `tolerance` x the sub-triangle's area share, at most
//! `max_depth` levels: smooth pairs cost 7-35 points, pairs that nearly touch more.
double triangle_to_polygon_view_factor(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                       const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& p,
                                       double tolerance = 1e-9, int max_depth = 7);

//! The part of the planar polygon `p` seen from x through the convex polygon `q`: `p` clipped
//! by the planes through x and each edge of `q` (the cone of directions from x that cross `q`
//! at a positive distance). Empty if none of it is, or if x lies in q's plane.
std::vector<Eigen::Vector3d> clip_polygon_to_cone(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& x,
                                                  const std::vector<Eigen::Vector3d>& q);

//! View factor [-] from the triangle (a, b, c), emitting along `n`, to the directions that
//! cross every polygon of `ps` (planar, convex, each at a positive distance, in any order),
//! unoccluded: at each point x, ps[0] clipped to the front half space and to the cones from x
//! over the others (clip_polygon_to_cone), by the same adaptive rule. The share of rays that
//! cross two hulls together: the joint means of planar_strata.h's crossing indicators.
double triangle_to_polygons_view_factor(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                        const Eigen::Vector3d& n, const std::vector<std::vector<Eigen::Vector3d>>& ps,
                                        double tolerance = 1e-9, int max_depth = 7);

}  // namespace thermodec
