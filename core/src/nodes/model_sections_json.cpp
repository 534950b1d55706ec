// The model file's environment and analysis sections, written with the keys model_sections.cpp
// reads: one place for the spelling, so that every JSON showing them pastes back into a model.
#include "thermodec/nodes/model_sections.h"

#include "thermodec/nodes/central_body.h"

namespace thermodec {

const char* attitude_name(Attitude a) {
  switch (a) {
    case Attitude::nadir: return "nadir";
    case Attitude::sun: return "sun";
    case Attitude::inertial: return "inertial";
  }
  return "nadir";
}

nlohmann::ordered_json environment_json(const Environment& e) {
  if (e.type == EnvironmentType::fixed_sun)
    return {{"type", "fixed_sun"},
            {"sun_direction", {e.sun_direction.x(), e.sun_direction.y(), e.sun_direction.z()}},
            {"solar_flux", e.solar_flux_W_per_m2}};
  nlohmann::ordered_json j = {{"type", "orbit"},        {"altitude_km", e.altitude_km}, {"inclination_deg", e.inclination_deg},
                              {"raan_deg", e.raan_deg}, {"day_of_year", e.day_of_year}, {"attitude", attitude_name(e.attitude)},
                              {"albedo", e.albedo},     {"earth_ir_flux", e.earth_ir_flux_W_per_m2}};
  // A table row by name (its albedo and IR are written apart, above); other bodies in full [km, km^3/s^2, AU].
  const CentralBody* row = find_central_body(e.central_body);
  const bool is_row = row && row->radius_m == e.body_radius_m && row->sun_distance_au == e.sun_distance_au &&
                      row->gravitational_parameter_m3_per_s2 == e.body_gravitational_parameter_m3_per_s2;
  if (!is_row)
    j["central_body"] = {{"name", e.central_body}, {"radius_km", e.body_radius_m / 1e3},
                         {"gm_km3_per_s2", e.body_gravitational_parameter_m3_per_s2 / 1e9},
                         {"albedo", e.albedo}, {"ir_flux", e.earth_ir_flux_W_per_m2}, {"sun_distance_au", e.sun_distance_au}};
  else if (e.central_body != "earth")
    j["central_body"] = e.central_body;
  return j;
}

nlohmann::ordered_json analysis_json(const Analysis& a) {
  if (a.type == AnalysisType::steady) return {{"type", "steady"}};
  nlohmann::ordered_json j = {{"type", "transient_orbit"}, {"steps_per_orbit", a.steps_per_orbit}, {"orbits", a.orbits}};
  if (a.time_tolerance_K != Analysis{}.time_tolerance_K) j["time_tolerance_K"] = a.time_tolerance_K;
  return j;
}

}  // namespace thermodec
