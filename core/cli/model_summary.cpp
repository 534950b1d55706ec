// Which environment and analysis a command used, in words (info, simulate) and as JSON.
#include <fmt/format.h>

#include "commands.h"
#include "thermodec/nodes/model_sections.h"

namespace thermodec::cli {

nlohmann::ordered_json environment_analysis_json(const ThermalModel& model) {
  return {{"environment", environment_json(model.environment)}, {"analysis", analysis_json(model.analysis)}};
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
