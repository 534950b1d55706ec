#pragma once
//! Geometry every computation can handle: coordinates finite and within ±kMaxCoordinate, so that
//! areas, normals, the bounding box, distances and loads are finite numbers. A mesh with a vertex
//! near ±1e308 is finite itself, but its edges and areas overflow to inf and NaN.
#include <Eigen/Core>
#include <string>

namespace thermodec {

//! Largest coordinate magnitude accepted [mesh units; m once scaled]. The ray tracer (Embree)
//! stores coordinates in single precision (max 3.4e38) and its intersection test forms products
//! of up to three lengths: (2 x 1e12)^3 = 8e36 stays finite; in double precision areas stay
//! below 1e25 m^2. 1e12 m is seven times the distance to the Sun: no spacecraft model comes near.
constexpr double kMaxCoordinate = 1e12;

//! Refuses vertices that are not finite or lie beyond ±kMaxCoordinate, and faces whose area is
//! not finite. `V`: #V x 3, `F`: #F x 3 with valid indices. `file` names the input in messages.
//! \throw InvalidInput "FILE: vertex N: ..." naming the first vertex at fault.
void check_geometry_range(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::string& file);

}  // namespace thermodec
