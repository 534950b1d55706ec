#pragma once
//! Plain CSV tables of an exported network (RFC 4180, '.' decimal point, header row):
//!  - temperatures: `time_s,<node>,...` one row per time [s, K];
//!  - couplings: `from,to,type,value,unit` with GL [W/K] and GR [m^2] (to "space" for GR to
//!    deep space), every pair once (from < to);
//!  - loads: `time_s,node,solar_W,albedo_W,earth_ir_W,internal_W`.
#include <filesystem>
#include <vector>

#include "thermodec/exchange/exported_network.h"

namespace thermodec {

//! Writes `<prefix>_temperatures.csv`, `<prefix>_couplings.csv`, `<prefix>_loads.csv` atomically
//! and returns their paths. \throw InvalidInput on a protected path; IOError on write failure.
std::vector<std::filesystem::path> write_csv_tables(const std::filesystem::path& prefix, const ExportedNetwork& network,
                                                    const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
