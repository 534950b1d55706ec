#pragma once
//! ESATAN-TMS thermal network input (.d file, ESATAN language): $MODEL, $LOCALS with $NODES
//! (diffusion D-nodes: label, T, C, A, ALP, EPS, QI; arithmetic nodes for C = 0; boundary
//! B-nodes for fixed temperatures and deep space), $CONDUCTORS (GL(i, j) [W/K], GR(i, j) [m^2]),
//! $CONSTANTS ($CONTROL: TABS = 0 so that temperatures are K, STEFAN, time step and end; $REAL:
//! the period), $ARRAYS (per node, doublet time tables of the absorbed solar, albedo and Earth-IR
//! loads over one orbit [s, W]), $VARIABLES1 (QS/QA/QE interpolated cyclically at TIMEM),
//! $EXECUTION (SOLVFM steady, or SLCRNC transient over `orbits` orbits after an SOLVFM start),
//! $OUTPUTS, $ENDMODEL. Node numbers: thermal node k -> k+1; deep space -> 99999.
#include <filesystem>
#include <vector>

#include "thermodec/exchange/exported_network.h"

namespace thermodec {

//! Writes `network` atomically at `path`.
//! \throw InvalidInput if `path` is one of `protected_inputs`; IOError on write failure.
void write_esatan_network(const std::filesystem::path& path, const ExportedNetwork& network,
                          const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
