#pragma once
//! Absorbed external heat loads per thermal node and time step (plain data), the input of the
//! thermal solvers. Computed by environment/external_loads.h; kept separate so that a caller
//! (the reduction driver) can reuse or combine loads without the ray tracer.
#include <Eigen/Core>
#include <vector>

namespace thermodec {

struct Loads {
  //! S sample times [s] (k P / S for an orbit; a single 0 for a fixed sun).
  Eigen::VectorXd times_s;
  //! Orbit period P [s]; 0 for a fixed sun (no orbit, loads constant).
  double period_s = 0.0;
  //! N x S absorbed powers [W], per component. solar: direct sunlight; albedo: sunlight
  //! reflected by the Earth; earth_ir: Earth infrared; reflected_solar: solar-band power
  //! (direct + albedo) reflected diffusely between the spacecraft's own faces.
  Eigen::MatrixXd solar_W, albedo_W, earth_ir_W, reflected_solar_W;
  //! N x S sampling standard error [W] of the absorbed loads: the binomial error of the albedo
  //! and Earth IR from their finite Earth rays (partly blocked sides, Earth fixed in body axes),
  //! and the direct sun's shadow samples on partly lit sides, sqrt(p (1 - p)) N^-3/4 on the lit
  //! share p of N scrambled-net points (a smooth shadow edge; the binomial sqrt(p (1 - p) / N)
  //! overstates it ~16x). An estimate for noise-targeted sampling (thermal/temperature_noise.h).
  //! Earth terms: sides reused whole from a reference add nothing.
  Eigen::MatrixXd sampling_standard_error_W;
  //! N sampling standard error [W] of the orbit mean of the absorbed loads (what a steady
  //! analysis solves for): the mean over steps of sampling_standard_error_W, except that shadow
  //! errors of passes with their own sample points (ExternalLoadSettings::steady_shadow_passes)
  //! add as independent errors. Empty when not computed.
  Eigen::VectorXd orbit_mean_standard_error_W;
  //! S flags: spacecraft in the Earth's shadow.
  std::vector<char> in_shadow;

  //! Eclipse edges (an orbit with eclipse, ExternalLoadSettings::eclipse_edges): the E shadow
  //! entry and exit instants [s] in [0, P), sorted (environment/orbit.h, eclipse_switch_times_s),
  //! and the loads there on the sunlit side, N x E per component [W]: what the direct sun reaches
  //! just before entry and just after exit, so that the interpolation between positions
  //! (thermal/orbit_transient.h) ends each sunlit arc on a traced value instead of an
  //! extrapolated one. Empty when not traced.
  Eigen::VectorXd edge_times_s;
  Eigen::MatrixXd edge_solar_W, edge_albedo_W, edge_earth_ir_W, edge_reflected_solar_W;

  //! Sum of the components, N x S [W].
  Eigen::MatrixXd total_W() const { return solar_W + albedo_W + earth_ir_W + reflected_solar_W; }
  //! Sum of the components at the eclipse edges, N x E [W].
  Eigen::MatrixXd edge_total_W() const { return edge_solar_W + edge_albedo_W + edge_earth_ir_W + edge_reflected_solar_W; }
  bool has_edges() const { return edge_times_s.size() > 0 && edge_solar_W.cols() == edge_times_s.size(); }
  int num_steps() const { return static_cast<int>(times_s.size()); }
};

}  // namespace thermodec
