// Sun position: Astronomical Almanac "low precision formulae for the Sun" (accuracy ~0.01 deg
// for 1950-2050), evaluated for year 2025; the day of year is what the analysis specifies.
#include "thermodec/environment/orbit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "thermodec/common/errors.h"

namespace thermodec {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

double days_since_j2000(int day_of_year) {
  if (day_of_year < 1 || day_of_year > 366)
    throw InvalidInput("environment.day_of_year must be in 1..366, got " + std::to_string(day_of_year));
  // 2025-01-01 12:00 UTC is JD 2460677.0, J2000.0 is JD 2451545.0.
  return 9132.0 + (day_of_year - 1);
}

double mean_anomaly_rad(double n) { return std::fmod(357.528 + 0.9856003 * n, 360.0) * kDeg; }

Eigen::Vector3d orbit_normal_eci(const Environment& env) {
  const double i = env.inclination_deg * kDeg, raan = env.raan_deg * kDeg;
  return {std::sin(raan) * std::sin(i), -std::cos(raan) * std::sin(i), std::cos(i)};
}

}  // namespace

Eigen::Vector3d sun_direction_eci(int day_of_year) {
  const double n = days_since_j2000(day_of_year);
  const double L = std::fmod(280.460 + 0.9856474 * n, 360.0) * kDeg;
  const double g = mean_anomaly_rad(n);
  const double lambda = L + (1.915 * std::sin(g) + 0.020 * std::sin(2 * g)) * kDeg;
  const double eps = (23.439 - 0.0000004 * n) * kDeg;
  return Eigen::Vector3d(std::cos(lambda), std::cos(eps) * std::sin(lambda),
                         std::sin(eps) * std::sin(lambda))
      .normalized();
}

double sun_distance_au(int day_of_year) {
  const double g = mean_anomaly_rad(days_since_j2000(day_of_year));
  return 1.00014 - 0.01671 * std::cos(g) - 0.00014 * std::cos(2 * g);
}

double solar_flux_on_day_W_per_m2(int day_of_year) {
  const double d = sun_distance_au(day_of_year);
  return kSolarConstantAt1AU_W_per_m2 / (d * d);
}

double solar_flux_W_per_m2(const Environment& env) {
  if (env.sun_distance_au > 0.0) return kSolarConstantAt1AU_W_per_m2 / (env.sun_distance_au * env.sun_distance_au);
  return solar_flux_on_day_W_per_m2(env.day_of_year);
}

double orbit_radius_m(const Environment& env) {
  if (!(env.altitude_km > 0.0))
    throw InvalidInput("environment.altitude_km must be > 0, got " + std::to_string(env.altitude_km));
  return env.body_radius_m + env.altitude_km * 1e3;
}

double orbit_period_s(const Environment& env) {
  const double r = orbit_radius_m(env);
  return 2.0 * kPi * std::sqrt(r * r * r / env.body_gravitational_parameter_m3_per_s2);
}

double orbit_radius_m(double altitude_km) {
  if (!(altitude_km > 0.0))
    throw InvalidInput("environment.altitude_km must be > 0, got " + std::to_string(altitude_km));
  return kEarthRadius_m + altitude_km * 1e3;
}

double orbit_period_s(double altitude_km) {
  const double r = orbit_radius_m(altitude_km);
  return 2.0 * kPi * std::sqrt(r * r * r / kEarthGravitationalParameter_m3_per_s2);
}

bool in_cylindrical_shadow(const Eigen::Vector3d& r, const Eigen::Vector3d& s, double radius_m) {
  const double along = r.dot(s);
  return along < 0.0 && (r - along * s).squaredNorm() < radius_m * radius_m;
}

OrbitState orbit_state(const Environment& env, double time_s) {
  const double radius = orbit_radius_m(env);
  const double period = orbit_period_s(env);
  const double i = env.inclination_deg * kDeg, raan = env.raan_deg * kDeg;
  const double u = 2.0 * kPi * time_s / period;  // argument of latitude, 0 at the ascending node
  // Perifocal-to-ECI for a circular orbit: position along P(u), velocity along Q(u).
  const Eigen::Vector3d node(std::cos(raan), std::sin(raan), 0.0);
  const Eigen::Vector3d in_plane_90(-std::sin(raan) * std::cos(i), std::cos(raan) * std::cos(i),
                                    std::sin(i));
  const Eigen::Vector3d r_hat = std::cos(u) * node + std::sin(u) * in_plane_90;
  const Eigen::Vector3d v_hat = -std::sin(u) * node + std::cos(u) * in_plane_90;
  const Eigen::Vector3d h_hat = r_hat.cross(v_hat);

  OrbitState st;
  st.time_s = time_s;
  st.position_eci_m = radius * r_hat;
  st.sun_direction_eci = sun_direction_eci(env.day_of_year);
  const Eigen::Vector3d& s = st.sun_direction_eci;

  Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  switch (env.attitude) {
    case Attitude::nadir:
      z = -r_hat;
      x = v_hat;
      y = z.cross(x);
      break;
    case Attitude::sun: {
      x = s;
      Eigen::Vector3d n = -(h_hat - h_hat.dot(s) * s);
      // Sun in the orbit normal direction (beta = 90 deg): any perpendicular will do; take
      // the one nearest ECI Z (or X) so the choice is still deterministic.
      if (n.norm() < 1e-9) n = Eigen::Vector3d::UnitZ() - s.z() * s;
      if (n.norm() < 1e-9) n = Eigen::Vector3d::UnitX() - s.x() * s;
      y = n.normalized();
      z = x.cross(y);
      break;
    }
    case Attitude::inertial:
      x = Eigen::Vector3d::UnitX();
      y = Eigen::Vector3d::UnitY();
      z = Eigen::Vector3d::UnitZ();
      break;
  }
  st.body_to_eci.col(0) = x;
  st.body_to_eci.col(1) = y;
  st.body_to_eci.col(2) = z;
  st.sun_direction_body = st.body_to_eci.transpose() * s;
  st.earth_direction_body = st.body_to_eci.transpose() * (-r_hat);
  st.in_shadow = in_cylindrical_shadow(st.position_eci_m, s, env.body_radius_m);
  return st;
}

double beta_angle_rad(const Environment& env) {
  const double sin_beta = orbit_normal_eci(env).dot(sun_direction_eci(env.day_of_year));
  return std::asin(std::clamp(sin_beta, -1.0, 1.0));
}

double eclipse_fraction(const Environment& env) {
  const double r = orbit_radius_m(env), R = env.body_radius_m;
  const double h = r - R;
  const double beta = beta_angle_rad(env);
  if (std::abs(beta) >= std::asin(R / r)) return 0.0;
  const double c = std::sqrt(h * h + 2.0 * R * h) / (r * std::cos(beta));
  return std::acos(std::clamp(c, -1.0, 1.0)) / kPi;
}

Eigen::VectorXd eclipse_switch_times_s(const Environment& env, double period_s) {
  // The shadow is a single arc per orbit (cylinder): scan finely enough to see any arc longer
  // than 1/720 of the orbit (shorter ones change no temperature measurably), then bisect.
  constexpr int kScan = 720;
  auto shadow = [&](double t) { return orbit_state(env, t).in_shadow; };
  std::vector<double> out;
  bool prev = shadow(0.0);
  for (int k = 1; k <= kScan; ++k) {
    double lo = period_s * (k - 1) / kScan, hi = period_s * k / kScan;
    const bool cur = shadow(k == kScan ? 0.0 : hi);
    if (cur == prev) continue;
    while (hi - lo > 1e-9 * period_s) {
      const double mid = 0.5 * (lo + hi);
      (shadow(mid) == prev ? lo : hi) = mid;
    }
    out.push_back(hi < period_s ? hi : 0.0);
    prev = cur;
  }
  std::sort(out.begin(), out.end());
  return Eigen::Map<Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size()));
}

int sun_passes(const std::vector<OrbitState>& states) {
  int passes = 0;
  const OrbitState* last_pass = nullptr;
  for (const OrbitState& st : states) {
    if (st.in_shadow) continue;
    if (!last_pass || !same_direction(st.sun_direction_body, last_pass->sun_direction_body)) {
      ++passes;
      last_pass = &st;
    }
  }
  return passes;
}

bool earth_fixed_in_body(const std::vector<OrbitState>& states) {
  for (std::size_t k = 1; k < states.size(); ++k)
    if (!same_direction(states[k].earth_direction_body, states[0].earth_direction_body)) return false;
  return true;
}

}  // namespace thermodec
