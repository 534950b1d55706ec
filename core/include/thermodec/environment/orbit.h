#pragma once
//! Circular orbit geometry around the environment's central body (the Earth by default; the
//! same formulae with its radius and GM for the Moon or Mars): sun position from the date, spacecraft position, attitude
//! (body axes), cylindrical Earth shadow and the geometric eclipse fraction.
//!
//! Frames. ECI: X towards the vernal equinox, Z towards the north pole (mean equator and
//! equinox of date; precession ignored). Body axes by attitude (docs/thermal.md):
//!  - nadir:    +Z towards the Earth centre (nadir), +X along the velocity (ram),
//!              +Y = Z x X (opposite to the orbit normal). The Earth is fixed in body axes.
//!  - sun:      +X towards the sun, +Y along minus the orbit normal made perpendicular to
//!              the sun, +Z = X x Y. The sun is fixed in body axes; the Earth circles.
//!  - inertial: body axes = ECI axes.
//! Time t = 0 is the ascending node crossing. The sun is held fixed over one orbit.
#include <Eigen/Core>
#include <vector>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

constexpr double kEarthRadius_m = 6371.0e3;                //!< mean Earth radius
constexpr double kEarthGravitationalParameter_m3_per_s2 = 3.986004418e14;
//! Total solar irradiance at 1 AU [W/m^2]. 1367 (WMO 1981, still ESATAN/ECSS practice) gives
//! 1322-1414 W/m^2 over the year; the 2011 measurement (1361) would shift all by -0.4 %.
constexpr double kSolarConstantAt1AU_W_per_m2 = 1367.0;
constexpr double kStefanBoltzmann_W_per_m2_K4 = 5.670374419e-8;
constexpr double kDeepSpaceTemperature_K = 2.7;

//! Unit vector from the Earth to the sun in ECI for a day of year (1..366, at 12:00 UTC,
//! year 2025), by the Astronomical Almanac low-precision formulae (about 0.01 deg).
//! \throw InvalidInput if day_of_year is outside 1..366.
Eigen::Vector3d sun_direction_eci(int day_of_year);

//! Earth-sun distance [AU] on that day (same formulae).
double sun_distance_au(int day_of_year);

//! Solar flux at the Earth on that day [W/m^2]: kSolarConstantAt1AU / distance^2
//! (about 1414 early January, 1322 early July).
double solar_flux_on_day_W_per_m2(int day_of_year);

//! Solar flux at the environment's central body [W/m^2]: kSolarConstantAt1AU / d^2 with d its
//! sun_distance_au, or solar_flux_on_day_W_per_m2(day_of_year) when that is 0 (Earth, Moon).
double solar_flux_W_per_m2(const Environment& environment);

//! Orbit radius [m] of a circular Earth orbit at `altitude_km`.
double orbit_radius_m(double altitude_km);

//! Period [s] of a circular Earth orbit at `altitude_km`. \throw InvalidInput if altitude <= 0.
double orbit_period_s(double altitude_km);

//! Orbit radius [m] around the environment's central body: body_radius_m + altitude.
//! \throw InvalidInput if altitude <= 0.
double orbit_radius_m(const Environment& environment);

//! Period [s] around the environment's central body: 2 pi sqrt(r^3 / GM).
//! \throw InvalidInput if altitude <= 0.
double orbit_period_s(const Environment& environment);

//! Spacecraft state at one instant of a circular orbit.
struct OrbitState {
  double time_s = 0.0;
  Eigen::Vector3d position_eci_m;       //!< from the Earth centre [m]
  Eigen::Matrix3d body_to_eci;          //!< columns = body X, Y, Z axes expressed in ECI
  Eigen::Vector3d sun_direction_body;   //!< unit vector towards the sun, body axes
  Eigen::Vector3d earth_direction_body; //!< unit vector towards the Earth centre, body axes
  Eigen::Vector3d sun_direction_eci;    //!< unit vector towards the sun, ECI
  bool in_shadow = false;               //!< inside the cylindrical Earth shadow
};

//! State at time `time_s` [s] after the ascending node for an orbit environment.
//! \throw InvalidInput on impossible elements (altitude <= 0, day outside 1..366).
OrbitState orbit_state(const Environment& environment, double time_s);

//! Two unit directions the loads treat as one (|a - b| < 1e-12).
inline bool same_direction(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm() < 1e-12; }

//! Shadow entry/exit instants [s] in [0, period_s) of the cylindrical Earth shadow
//! (orbit_state().in_shadow), sorted, located by bisection to 1e-9 of the period.
Eigen::VectorXd eclipse_switch_times_s(const Environment& environment, double period_s);

//! Shadow passes of the direct sun over the time steps `states`: a sunlit step whose sun
//! direction in body axes differs from the last pass's starts a new one (one for a sun-pointing
//! or inertial attitude; one per sunlit step for a nadir-pointing orbit). The loads trace one
//! shadow computation per pass; the cost estimate counts them the same way.
int sun_passes(const std::vector<OrbitState>& states);

//! Whether the Earth direction in body axes is the same in every state (a nadir-pointing
//! attitude): the Earth rays are then traced once for all steps.
bool earth_fixed_in_body(const std::vector<OrbitState>& states);

//! True if `position_eci_m` lies in the cylindrical shadow of a body of radius `radius_m`
//! cast along `sun_direction` (unit).
bool in_cylindrical_shadow(const Eigen::Vector3d& position_eci_m,
                           const Eigen::Vector3d& sun_direction, double radius_m = kEarthRadius_m);

//! Angle beta [rad] between the sun direction and the orbit plane (signed, + on the side of
//! the orbit normal).
double beta_angle_rad(const Environment& environment);

//! Fraction of the orbit spent in the cylindrical shadow, closed form:
//! f = acos( sqrt(h^2 + 2 R h) / (r cos beta) ) / pi if |beta| < asin(R / r), else 0.
double eclipse_fraction(const Environment& environment);

}  // namespace thermodec
