#pragma once
//! The "environment" and "analysis" sections of a model file (docs/model-format.md) written from
//! their values, with the keys load_model reads: save_model writes them, `thermodec info --json`
//! and the result JSON of `simulate` show them, so that either pastes back into a model file.
#include <nlohmann/json.hpp>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

//! `{"type": "fixed_sun", "sun_direction": [...], "solar_flux": W/m^2}` or the orbit's keys
//! (altitude_km, inclination_deg, raan_deg, day_of_year, attitude, albedo, earth_ir_flux [W/m^2],
//! and central_body when it is not the Earth).
nlohmann::ordered_json environment_json(const Environment& environment);

//! The model file's word for an attitude: "nadir", "sun" or "inertial".
const char* attitude_name(Attitude attitude);

//! `{"type": "steady"}` or `{"type": "transient_orbit", "steps_per_orbit", "orbits"}`, with
//! time_tolerance_K [K] when it is not the default.
nlohmann::ordered_json analysis_json(const Analysis& analysis);

}  // namespace thermodec
