#pragma once
//! ESATAN-TMS thermal network input (.d file, ESATAN language, laid out as ESATAN-TMS's own
//! generated .d files): $MODEL, $LOCALS, $NODES (diffusion D-nodes: label, T, C, A, ALP, EPS, QI;
//! arithmetic A-nodes for C = 0; boundary B-nodes for fixed temperatures and deep space),
//! $CONDUCTORS (GL(i, j) [W/K], GR(i, j) [m^2]), $CONSTANTS ($REAL: the period; $CONTROL:
//! TABS = 0 so that temperatures are K, STEFAN, time step and end), $ARRAYS (per node, doublet
//! time tables of the absorbed solar, albedo and Earth-IR loads over one orbit [s, W]),
//! $EXECUTION (CALL SOLVFM; transient: CALL SOLCYC('SLCRNC', ...) to the orbit-periodic state,
//! then CALL SLCRNC over the output orbit), $VARIABLES1 (QS(n), QA(n), QE(n) interpolated
//! cyclically at TIMEM with INTCY1), $OUTPUTS, $ENDMODEL. Reals carry D exponents. Node
//! numbers: thermal node k -> k+1; deep space -> 99999.

#include "thermodec/exchange/exported_network.h"

namespace thermodec {

//! Writes `network` atomically at `path`.
//! \throw InvalidInput if `path` is one of `protected_inputs`; IOError on write failure.
void write_esatan_network(const std::filesystem::path& path, const ExportedNetwork& network,
                          const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
