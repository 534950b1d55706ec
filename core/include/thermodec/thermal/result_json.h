#pragma once
//! The simulation result file (`thermodec simulate --json`):
//! {"nodes": [..], "times_s": [..], "temperatures_K": {"<node>": [..]},
//!  "loads_W": {"<node>": {"solar": [..], "albedo": [..], "earth_ir": [..],
//!              "reflected_solar": [..], "internal": x, "total": [..]}},
//!  "in_shadow": [..], "summary": {"<node>": {"min_K", "mean_K", "max_K"}},
//!  "analysis": "steady" | "transient_orbit", "period_s": P, "solver": {...}}
#include <filesystem>
#include <nlohmann/json.hpp>

#include "thermodec/thermal/simulate.h"

namespace thermodec {

nlohmann::json result_to_json(const SimulationResult& result);

//! Reads back nodes, times and temperatures (what compare_results needs).
//! \throw InvalidInput naming the missing/malformed key.
SimulationResult result_from_json(const nlohmann::json& json);

//! Reads a result file. \throw IOError if unreadable, InvalidInput (with the path) if malformed.
SimulationResult read_result(const std::filesystem::path& path);

}  // namespace thermodec
