// The environment, analysis and radiation sections of model and load-case files.
#include <cmath>
#include <cstdint>

#include "model_json.h"

namespace thermodec::model_json {

namespace {

std::string known_body_names() {
  std::string s;
  for (const CentralBody& b : central_bodies()) s += (s.empty() ? "" : ", ") + b.name;
  return s;
}

// "central_body": a name of the table, or an object {name, radius_km, gm_km3_per_s2, albedo,
// ir_flux, sun_distance_au}: a known name's row with the numbers given overriding it, or an
// unknown name with all five numbers.
CentralBody parse_central_body(const json& j, const Keys& k) {
  const std::string key = "environment.central_body";
  if (j.is_string()) {
    const CentralBody* b = find_central_body(j.get<std::string>());
    if (!b) k.fail(key, "unknown body '" + j.get<std::string>() + "' (known: " + known_body_names() + "; or an object with the numbers)");
    return *b;
  }
  if (!j.is_object()) k.fail(key, "must be a body name (" + known_body_names() + ") or an object with its numbers");
  k.only_keys(j, key, {"name", "radius_km", "gm_km3_per_s2", "albedo", "ir_flux", "sun_distance_au"}, "");
  if (!j.contains("name")) k.fail(key, "missing 'name'");
  const std::string name = k.string(j, key, "name");
  const CentralBody* row = find_central_body(name);
  CentralBody b = row ? *row : CentralBody{};
  b.name = name;
  for (const char* n : {"radius_km", "gm_km3_per_s2", "albedo", "ir_flux", "sun_distance_au"})
    if (!row && !j.contains(n)) k.fail(key, "'" + name + "' is not a known body (" + known_body_names() + "): give '" + n + "' too");
  if (j.contains("radius_km")) b.radius_m = 1e3 * k.number_in(j, key, "radius_km", 0, 1e6, true, " km");
  if (j.contains("gm_km3_per_s2")) b.gravitational_parameter_m3_per_s2 = 1e9 * k.number_in(j, key, "gm_km3_per_s2", 0, 1e9, true, " km^3/s^2");
  if (j.contains("albedo")) b.albedo = k.number_in(j, key, "albedo", 0, 1, false, "");
  if (j.contains("ir_flux")) b.ir_flux_W_per_m2 = k.number_in(j, key, "ir_flux", 0, 1e4, false, " W/m^2");
  if (j.contains("sun_distance_au")) b.sun_distance_au = k.number_in(j, key, "sun_distance_au", 0, 1e3, false, " AU");
  return b;
}

}  // namespace

void parse_environment(const json& j, const Keys& k, Environment& env) {
  const std::string key = "environment";
  k.require_object(j, key);
  if (!j.contains("type")) k.fail(key, "missing 'type' (fixed_sun or orbit)");
  const std::string type = k.string(j, key, "type");
  if (type == "fixed_sun") {
    env.type = EnvironmentType::fixed_sun;
    k.only_keys(j, key, {"type", "sun_direction", "solar_flux"}, " for type fixed_sun");
    if (j.contains("sun_direction")) {
      const json& d = j.at("sun_direction");
      if (!d.is_array() || d.size() != 3) k.fail(key + ".sun_direction", "must be an array of 3 numbers");
      Eigen::Vector3d v;
      for (int i = 0; i < 3; ++i) {
        if (!d[i].is_number() || !std::isfinite(d[i].get<double>())) k.fail(key + ".sun_direction", "must be an array of 3 finite numbers");
        v[i] = d[i].get<double>();
      }
      // Stable norm: [1, 0, 1e308] overflows the plain one (its direction would become zero)
      // and [1e-200, 0, 0] underflows it (a valid direction refused as zero).
      if (!(v.stableNorm() > 0)) k.fail(key + ".sun_direction", "must not be the zero vector");
      env.sun_direction = v.stableNormalized();
    }
    if (j.contains("solar_flux")) env.solar_flux_W_per_m2 = k.number_in(j, key, "solar_flux", 0, 1e7, false, " W/m^2");
  } else if (type == "orbit") {
    env.type = EnvironmentType::orbit;
    k.only_keys(j, key, {"type", "altitude_km", "inclination_deg", "raan_deg", "day_of_year", "attitude", "central_body", "albedo", "earth_ir_flux"},
                " for type orbit");
    if (j.contains("altitude_km")) env.altitude_km = k.number_in(j, key, "altitude_km", 0, 1e6, true, " km");
    if (j.contains("inclination_deg")) env.inclination_deg = k.number_in(j, key, "inclination_deg", 0, 180, false, " deg");
    if (j.contains("raan_deg")) env.raan_deg = k.number_in(j, key, "raan_deg", -360, 360, false, " deg");
    if (j.contains("day_of_year")) env.day_of_year = static_cast<int>(k.integer(j, key, "day_of_year", 1, 366));
    if (j.contains("attitude")) {
      const std::string a = k.string(j, key, "attitude");
      if (a == "nadir") env.attitude = Attitude::nadir;
      else if (a == "sun") env.attitude = Attitude::sun;
      else if (a == "inertial") env.attitude = Attitude::inertial;
      else k.fail(key + ".attitude", "unknown attitude '" + a + "' (known: nadir, sun, inertial)");
    }
    // The body first: its albedo and IR are the defaults the two keys below override.
    if (j.contains("central_body")) set_central_body(env, parse_central_body(j.at("central_body"), k));
    if (j.contains("albedo")) env.albedo = k.number_in(j, key, "albedo", 0, 1, false, "");
    if (j.contains("earth_ir_flux")) env.earth_ir_flux_W_per_m2 = k.number_in(j, key, "earth_ir_flux", 0, 1e4, false, " W/m^2");
  } else {
    k.fail(key + ".type", "unknown environment type '" + type + "' (known: fixed_sun, orbit)");
  }
}

std::vector<std::pair<double, double>> power_schedule(const json& j, const Keys& k, const std::string& key) {
  if (!j.is_array() || j.empty()) k.fail(key, "must be a non-empty array of [t_s, W] pairs");
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const json& p = j[i];
    const std::string at = key + "[" + std::to_string(i) + "]";
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) k.fail(at, "must be a pair [t_s, W] of numbers");
    const double t = p[0].get<double>(), w = p[1].get<double>();
    if (!std::isfinite(t) || !std::isfinite(w)) k.fail(at, "must be finite");
    if (i == 0 && t != 0.0) k.fail(at, "the first time must be 0 s (the schedule repeats every orbit)");
    if (i > 0 && !(t > out.back().first)) k.fail(at, "times must increase");
    out.emplace_back(t, w);
  }
  return out;
}

Thermostat thermostat(const json& j, const Keys& k, const std::string& key) {
  k.require_object(j, key);
  k.only_keys(j, key, {"on_K", "off_K", "power_W"}, "");
  for (const char* n : {"on_K", "off_K", "power_W"})
    if (!j.contains(n)) k.fail(key, std::string("missing '") + n + "' (a heater is {\"on_K\", \"off_K\", \"power_W\"})");
  Thermostat t;
  t.on_K = k.number_in(j, key, "on_K", 0, 1e5, true, " K");
  t.off_K = k.number_in(j, key, "off_K", 0, 1e5, true, " K");
  t.power_W = k.number_in(j, key, "power_W", 0, 1e12, true, " W");
  if (!(t.on_K < t.off_K)) k.fail(key, "on_K must be below off_K (the hysteresis band)");
  return t;
}

void check_internal_power(const ThermalModel& model, const Keys& k) {
  for (const Node& node : model.nodes) {
    const std::string key = "nodes." + node.name;
    if (node.heater && (node.fixed_temperature_K || !(node.capacitance_J_per_K > 0.0)))
      k.fail(key + ".heater", "a thermostat needs a free node with a capacitance > 0 J/K");
    if (node.heater && model.analysis.type != AnalysisType::transient_orbit)
      k.fail(key + ".heater", "a thermostat switches over time: it needs analysis.type transient_orbit");
    if (!node.power_schedule_W.empty() && model.environment.type != EnvironmentType::orbit)
      k.fail(key + ".power_schedule_W", "a schedule repeats every orbit: it needs an environment of type orbit");
  }
}

void parse_analysis(const json& j, const Keys& k, Analysis& a) {
  const std::string key = "analysis";
  k.require_object(j, key);
  if (!j.contains("type")) k.fail(key, "missing 'type' (steady or transient_orbit)");
  const std::string type = k.string(j, key, "type");
  if (type == "steady") {
    a.type = AnalysisType::steady;
    k.only_keys(j, key, {"type"}, " for type steady");
  } else if (type == "transient_orbit") {
    a.type = AnalysisType::transient_orbit;
    k.only_keys(j, key, {"type", "steps_per_orbit", "orbits", "time_tolerance_K"}, " for type transient_orbit");
    if (j.contains("steps_per_orbit")) a.steps_per_orbit = static_cast<int>(k.integer(j, key, "steps_per_orbit", 4, 1000000));
    if (j.contains("orbits")) a.orbits = static_cast<int>(k.integer(j, key, "orbits", 1, 10000));
    if (j.contains("time_tolerance_K")) a.time_tolerance_K = k.number_in(j, key, "time_tolerance_K", 0.0, 100.0, true, "K");
  } else {
    k.fail(key + ".type", "unknown analysis type '" + type + "' (known: steady, transient_orbit)");
  }
}

// Model files and load case files alike: an orbit transient needs an orbit.
void check_analysis_fits_environment(const Analysis& a, const Environment& e, const Keys& k) {
  if (a.type == AnalysisType::transient_orbit && e.type != EnvironmentType::orbit)
    k.fail("analysis.type", "transient_orbit needs an environment of type orbit (there is no orbit period otherwise)");
}

void parse_radiation(const json& j, const Keys& k, RadiationSettings& r) {
  const std::string key = "radiation";
  k.require_object(j, key);
  k.only_keys(j, key, {"rays_per_face", "min_rays_per_node", "seed"});
  // One side emits at most max(rays_per_face, min_rays_per_node) rays and the Sobol table
  // holds that many 16-byte points: 1e7 keeps it at 160 MB (40x the default
  // min_rays_per_node), where 1e9 would ask for 16 GB.
  constexpr long long kMaxRaysPerSide = 10000000;
  if (j.contains("rays_per_face")) r.rays_per_face = static_cast<int>(k.integer(j, key, "rays_per_face", 1, kMaxRaysPerSide));
  if (j.contains("min_rays_per_node"))
    r.min_rays_per_node = static_cast<int>(k.integer(j, key, "min_rays_per_node", 0, kMaxRaysPerSide));
  if (j.contains("seed")) {
    const json& s = j.at("seed");
    if (!s.is_number_unsigned() && !(s.is_number_integer() && s.get<long long>() >= 0))
      k.fail("radiation.seed", "must be an integer >= 0, got " + s.dump());
    r.seed = s.get<std::uint64_t>();
  }
}

}  // namespace thermodec::model_json
