#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

using namespace thermodec;

namespace {
constexpr double kPi = 3.14159265358979323846;
Environment leo(double inclination_deg, double raan_deg, int day) {
  Environment e;
  e.type = EnvironmentType::orbit;
  e.altitude_km = 500.0;
  e.inclination_deg = inclination_deg;
  e.raan_deg = raan_deg;
  e.day_of_year = day;
  return e;
}
}  // namespace

TEST(SolarFlux, spans_1322_to_1414_over_the_year_with_perihelion_in_january) {
  double lo = 1e9, hi = 0.0;
  int day_hi = 0, day_lo = 0;
  for (int d = 1; d <= 365; ++d) {
    const double s = solar_flux_on_day_W_per_m2(d);
    if (s > hi) hi = s, day_hi = d;
    if (s < lo) lo = s, day_lo = d;
  }
  EXPECT_NEAR(hi, 1414.0, 1.0);
  EXPECT_NEAR(lo, 1322.0, 1.0);
  EXPECT_LE(day_hi, 6);                 // perihelion ~ 3-4 January
  EXPECT_NEAR(day_lo, 185.0, 3.0);      // aphelion ~ 4 July
}

TEST(SunDirection, lies_on_the_equinox_and_solstice_axes) {
  // 20 March 2025 (day 79) is the March equinox: the sun crosses the equator along +X.
  const Eigen::Vector3d eq = sun_direction_eci(79);
  EXPECT_NEAR(eq.x(), 1.0, 1e-3);
  EXPECT_NEAR(eq.z(), 0.0, 0.01);  // within a day's motion (0.4 deg of declination)
  // 21 June (day 172): declination = obliquity 23.44 deg.
  const Eigen::Vector3d sol = sun_direction_eci(172);
  EXPECT_NEAR(std::asin(sol.z()) * 180.0 / kPi, 23.44, 0.05);
  EXPECT_THROW(sun_direction_eci(0), InvalidInput);
  EXPECT_THROW(sun_direction_eci(367), InvalidInput);
}

TEST(Orbit, period_at_500_km_matches_kepler) {
  const double r = kEarthRadius_m + 500e3;
  EXPECT_NEAR(orbit_period_s(500.0), 2 * kPi * std::sqrt(r * r * r / 3.986004418e14), 1e-6);
  EXPECT_NEAR(orbit_period_s(500.0), 5668.0, 1.0);
  EXPECT_THROW(orbit_period_s(-1.0), InvalidInput);
}

TEST(Orbit, eclipse_fraction_of_sampled_orbit_matches_geometric_formula) {
  for (double raan : {0.0, 40.0, 75.0}) {
    const Environment env = leo(51.6, raan, 80);
    const int n = 20000;
    int dark = 0;
    const double period = orbit_period_s(env.altitude_km);
    for (int k = 0; k < n; ++k) dark += orbit_state(env, period * (k + 0.5) / n).in_shadow;
    const double sampled = double(dark) / n;
    const double formula = eclipse_fraction(env);
    EXPECT_GT(formula, 0.2) << "raan " << raan;
    // Two shadow boundaries, each resolved to half a sample.
    EXPECT_NEAR(sampled, formula, 1.0 / n) << "raan " << raan;
  }
}

TEST(Orbit, dawn_dusk_orbit_facing_the_sun_has_no_eclipse) {
  // Day 79: sun along +X. Polar orbit with RAAN 90 deg: orbit normal = +X, beta ~ 90 deg.
  const Environment env = leo(90.0, 90.0, 79);
  EXPECT_GT(beta_angle_rad(env), 1.5);
  EXPECT_EQ(eclipse_fraction(env), 0.0);
  const double period = orbit_period_s(env.altitude_km);
  for (int k = 0; k < 100; ++k) EXPECT_FALSE(orbit_state(env, period * k / 100).in_shadow);
}

TEST(Attitude, nadir_axes_point_z_to_earth_and_x_along_velocity) {
  Environment env = leo(51.6, 30.0, 120);
  env.attitude = Attitude::nadir;
  const double period = orbit_period_s(env.altitude_km);
  for (double t : {0.0, 0.3 * period, 0.71 * period}) {
    const OrbitState s = orbit_state(env, t);
    const Eigen::Matrix3d R = s.body_to_eci;
    EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((s.earth_direction_body - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
    const OrbitState later = orbit_state(env, t + 1.0);
    const Eigen::Vector3d v = (later.position_eci_m - s.position_eci_m).normalized();
    EXPECT_NEAR(v.dot(R.col(0)), 1.0, 1e-6);
    EXPECT_NEAR(s.sun_direction_body.norm(), 1.0, 1e-12);
  }
}

TEST(Attitude, sun_pointing_holds_the_sun_on_plus_x_and_inertial_is_eci) {
  Environment env = leo(51.6, 30.0, 200);
  env.attitude = Attitude::sun;
  const double period = orbit_period_s(env.altitude_km);
  for (double t : {0.0, 0.5 * period}) {
    const OrbitState s = orbit_state(env, t);
    EXPECT_NEAR((s.sun_direction_body - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(s.body_to_eci.determinant(), 1.0, 1e-12);
  }
  env.attitude = Attitude::inertial;
  const OrbitState s = orbit_state(env, 0.25 * period);
  EXPECT_NEAR((s.sun_direction_body - sun_direction_eci(200)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((s.earth_direction_body + s.position_eci_m.normalized()).norm(), 0.0, 1e-12);
}

TEST(Attitude, shadow_passes_and_a_fixed_earth_follow_the_attitude) {
  // 24 steps of an orbit with an eclipse: nadir pointing sees the sun move in body axes (one
  // pass per sunlit step) and the Earth stay on +Z; sun pointing holds the sun (one pass) and
  // sees the Earth move; no step at all, no pass.
  Environment env = leo(51.6, 30.0, 80);
  const double period = orbit_period_s(env.altitude_km);
  auto states_of = [&](Attitude a) {
    env.attitude = a;
    std::vector<OrbitState> states;
    for (int k = 0; k < 24; ++k) states.push_back(orbit_state(env, period * k / 24));
    return states;
  };
  const std::vector<OrbitState> nadir = states_of(Attitude::nadir);
  int lit = 0;
  for (const OrbitState& s : nadir) lit += !s.in_shadow;
  ASSERT_GT(lit, 0);
  ASSERT_LT(lit, 24);
  EXPECT_EQ(sun_passes(nadir), lit);
  EXPECT_TRUE(earth_fixed_in_body(nadir));
  const std::vector<OrbitState> sun = states_of(Attitude::sun);
  EXPECT_EQ(sun_passes(sun), 1);
  EXPECT_FALSE(earth_fixed_in_body(sun));
  EXPECT_EQ(sun_passes({}), 0);
  EXPECT_TRUE(earth_fixed_in_body({}));
}
