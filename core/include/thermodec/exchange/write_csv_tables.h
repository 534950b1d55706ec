#pragma once
//! Plain CSV tables of an exported network (RFC 4180, '.' decimal point, header row):
//!  - temperatures: `time_s,<node>,...` one row per time [s, K];
//!  - couplings: `from,to,type,value,unit` with GL [W/K] and GR [m^2] (to "space" for GR to
//!    deep space), every pair once (from < to);
//!  - loads: `time_s,node,solar_W,albedo_W,earth_ir_W,internal_W` at the table points of the
//!    network (ExportedNetwork::table_times_s: the positions and both sides of every eclipse
//!    switch), to be interpolated linearly and cyclically over `period_s` (nodes table);
//!  - nodes: `node,kind,capacitance_J_per_K,internal_W,fixed_temperature_K,initial_temperature_K,
//!    area_m2,absorptivity,emissivity,period_s`: kind diffusion / arithmetic / boundary, the
//!    fixed temperature empty for free nodes, the initial temperature the periodic state at
//!    t = 0; a last row `space,boundary,...` carries the sink temperature. With those, the three
//!    other tables rebuild the transient. A reduced model's certificate (ExportedNetwork::
//!    provenance) leads this table as `# ` comment lines.
#include <filesystem>
#include <vector>

#include "thermodec/exchange/exported_network.h"

namespace thermodec {

//! Writes `<prefix>_temperatures.csv`, `<prefix>_couplings.csv`, `<prefix>_loads.csv`,
//! `<prefix>_nodes.csv` atomically
//! and returns their paths. \throw InvalidInput on a protected path; IOError on write failure.
std::vector<std::filesystem::path> write_csv_tables(const std::filesystem::path& prefix, const ExportedNetwork& network,
                                                    const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
