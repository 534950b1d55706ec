#pragma once
//! Load cases: the same spacecraft in other environments (hot and cold cases: another day of
//! the year, attitude, altitude, albedo, a fixed sun, ...). A reduced model is meant to replace
//! the detailed one in every case a thermal engineer runs, so the reduction can be verified
//! against several of them at once (ReduceSettings::extra_cases).
//!
//! A case file is a small JSON object (docs/model-format.md, "Load cases"):
//!   {"name": "cold", "environment": {...}, "analysis": {...}}
//! Both sections are read exactly like the model file's own (same keys, same checks), starting
//! from the base model's values: {"environment": {"type": "orbit", "day_of_year": 172}} moves
//! only the date. "name" defaults to the file's stem.
#include <filesystem>
#include <string>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

struct LoadCase {
  std::string name;
  Environment environment;
  Analysis analysis;
};

//! The model's own environment and analysis as a case named `name`.
LoadCase own_case(const ThermalModel& model, const std::string& name = "model");

//! Reads a case file over `base`'s environment and analysis.
//! \throw IOError if unreadable; InvalidInput naming the key (unknown key, bad value,
//! transient_orbit without an orbit, ...).
LoadCase load_case(const std::filesystem::path& path, const ThermalModel& base);

//! `model` with the case's environment and analysis (everything else shared).
//! \throw InvalidInput if a node's thermostat heater meets a case that is not transient_orbit,
//! or a power schedule a case without an orbit.
ThermalModel with_case(const ThermalModel& model, const LoadCase& c);

}  // namespace thermodec
