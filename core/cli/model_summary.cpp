// Which environment and analysis a command used, in words (info, simulate) and as JSON.
#include <fmt/format.h>

#include "commands.h"

namespace thermodec::cli {
namespace {
const char* attitude_name(Attitude a) {
  switch (a) {
    case Attitude::nadir: return "nadir";
    case Attitude::sun: return "sun";
    case Attitude::inertial: return "inertial";
  }
  return "?";
}
}  // namespace

nlohmann::ordered_json environment_analysis_json(const ThermalModel& model) {
  const Environment& e = model.environment;
  nlohmann::ordered_json env;
  if (e.type == EnvironmentType::fixed_sun) {
    env = {{"type", "fixed_sun"},
           {"sun_direction", {e.sun_direction.x(), e.sun_direction.y(), e.sun_direction.z()}},
           {"solar_flux_W_per_m2", e.solar_flux_W_per_m2}};
  } else {
    env = {{"type", "orbit"},           {"altitude_km", e.altitude_km}, {"inclination_deg", e.inclination_deg},
           {"raan_deg", e.raan_deg},    {"day_of_year", e.day_of_year}, {"attitude", attitude_name(e.attitude)},
           {"albedo", e.albedo},        {"earth_ir_flux_W_per_m2", e.earth_ir_flux_W_per_m2}};
  }
  nlohmann::ordered_json analysis;
  if (model.analysis.type == AnalysisType::steady)
    analysis = {{"type", "steady"}};
  else
    analysis = {{"type", "transient_orbit"}, {"steps_per_orbit", model.analysis.steps_per_orbit},
                {"orbits", model.analysis.orbits}};
  return {{"environment", env}, {"analysis", analysis}};
}

std::string environment_analysis_text(const ThermalModel& model) {
  const Environment& e = model.environment;
  std::string env = e.type == EnvironmentType::fixed_sun
                        ? fmt::format("fixed_sun, {:.6g} W/m^2 from ({:.3g}, {:.3g}, {:.3g})", e.solar_flux_W_per_m2,
                                      e.sun_direction.x(), e.sun_direction.y(), e.sun_direction.z())
                        : fmt::format("orbit, {:.6g} km, inclination {:.6g} deg, RAAN {:.6g} deg, day {}, attitude {}",
                                      e.altitude_km, e.inclination_deg, e.raan_deg, e.day_of_year, attitude_name(e.attitude));
  std::string analysis = model.analysis.type == AnalysisType::steady
                             ? std::string("steady")
                             : fmt::format("transient_orbit, {} steps per orbit, {} orbits", model.analysis.steps_per_orbit,
                                           model.analysis.orbits);
  return fmt::format("{:<20}{}\n{:<20}{}\n", "environment", env, "analysis", analysis);
}

}  // namespace thermodec::cli
