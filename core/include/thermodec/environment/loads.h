#pragma once
//! Absorbed external heat loads per thermal node and time step (plain data), the input of the
//! thermal solvers. Computed by environment/external_loads.h; kept separate so that a caller
//! (the reduction driver) can reuse or combine loads without the ray tracer.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace thermodec {

struct Loads {
  //! S sample times [s] (k P / S for an orbit; a single 0 for a fixed sun).
  Eigen::VectorXd times_s;
  //! Orbit period P [s]; 0 for a fixed sun (no orbit, loads constant).
  double period_s = 0.0;
  //! N x S absorbed powers [W], per component (load_components() lists them). solar: direct
  //! sunlight; albedo: sunlight reflected by the central body; earth_ir: the central body's
  //! infrared; reflected_solar: solar-band power (direct + albedo) reflected diffusely between
  //! the spacecraft's own faces.
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
  //! errors of passes with their own sample points (ExternalLoadSettings::steady_shadow_passes,
  //! ::transient_shadow_passes) add as independent errors. Empty when not computed.
  Eigen::VectorXd orbit_mean_standard_error_W;
  //! S flags: spacecraft in the Earth's shadow.
  std::vector<char> in_shadow;

  //! Sunlit knots: K instants [s] in [0, P), sorted, where the loads are traced besides the
  //! positions, and the loads there, N x K per component [W] (ExternalLoadSettings::eclipse_edges
  //! and ::kink_knot_threshold_K): every eclipse entry and exit on its sunlit side (what the
  //! direct sun reaches just before entry and just after exit), and the instants where a face
  //! turns edge-on to the sun, whose direct load has a kink there (max(0, n . s)). The
  //! interpolation between positions (thermal/orbit_transient.h) passes through them, so a
  //! sunlit arc ends on a traced value and a kink is not cut off by a straight line. Empty when
  //! none are traced.
  Eigen::VectorXd knot_times_s;
  Eigen::MatrixXd knot_solar_W, knot_albedo_W, knot_earth_ir_W, knot_reflected_solar_W;

  //! Sum of the components, N x S [W].
  Eigen::MatrixXd total_W() const;
  //! Sum of the components at the knots, N x K [W].
  Eigen::MatrixXd knot_total_W() const;
  bool has_knots() const { return knot_times_s.size() > 0 && knot_solar_W.cols() == knot_times_s.size(); }
  int num_steps() const { return static_cast<int>(times_s.size()); }
};

//! One external load component: its name (its key in result files, loads_W) and where Loads
//! keeps it, at the positions (N x S) and at the sunlit knots (N x K). `direct_sun`: the
//! component is switched at the eclipse (direct sunlight and its reflections, zero in shadow);
//! otherwise it varies smoothly over the orbit (albedo, the central body's IR).
struct LoadComponent {
  const char* name;
  Eigen::MatrixXd Loads::*W;
  Eigen::MatrixXd Loads::*knot_W;
  bool direct_sun;
};

//! The components of Loads, in the order every sum takes them. The interpolation in time, the
//! orbit means, the coarser sampling and the result file go through this table: a new external
//! component is a Loads member pair, its producer (environment/external_loads.h) and one row.
inline const std::array<LoadComponent, 4>& load_components() {
  static const std::array<LoadComponent, 4> table{{{"solar", &Loads::solar_W, &Loads::knot_solar_W, true},
                                                   {"albedo", &Loads::albedo_W, &Loads::knot_albedo_W, false},
                                                   {"earth_ir", &Loads::earth_ir_W, &Loads::knot_earth_ir_W, false},
                                                   {"reflected_solar", &Loads::reflected_solar_W, &Loads::knot_reflected_solar_W, true}}};
  return table;
}

inline Eigen::MatrixXd Loads::total_W() const {
  Eigen::MatrixXd t = this->*load_components()[0].W;
  for (std::size_t c = 1; c < load_components().size(); ++c) t += this->*load_components()[c].W;
  return t;
}

inline Eigen::MatrixXd Loads::knot_total_W() const {
  Eigen::MatrixXd t = this->*load_components()[0].knot_W;
  for (std::size_t c = 1; c < load_components().size(); ++c) t += this->*load_components()[c].knot_W;
  return t;
}

}  // namespace thermodec
