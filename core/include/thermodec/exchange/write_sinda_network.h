#pragma once
//! SINDA/FLUINT input (as Thermal Desktop writes it): HEADER OPTIONS DATA, HEADER CONTROL DATA
//! (UID = SI, ABSZRO = 0 so that temperatures are K, SIGMA, TIMEND, DTIMEI, OUTPUT interval), HEADER
//! NODE DATA ("id, T, C   $ name": diffusion C > 0; arithmetic C = -1.0; boundary: negative id
//! and C = -1.0, for fixed temperatures and deep space, node 99999), HEADER CONDUCTOR DATA (linear "id, a, b, G"
//! [W/K]; radiation "-id, a, b, GR" [m^2], SIGMA applied by SINDA), HEADER ARRAY DATA (per
//! node, doublet time tables of the absorbed external load over one orbit [s, W]), HEADER
//! VARIABLES 1 (Qn = internal power + the table interpolated cyclically at TIMEN with D11CYL,
//! or the orbit-averaged load for a steady analysis), HEADER OPERATIONS (STEADY, then TRANSIENT
//! for an orbit analysis), END OF DATA.
#include <filesystem>
#include <vector>

#include "thermodec/exchange/exported_network.h"

namespace thermodec {

//! Writes `network` atomically at `path`.
//! \throw InvalidInput if `path` is one of `protected_inputs`; IOError on write failure.
void write_sinda_network(const std::filesystem::path& path, const ExportedNetwork& network,
                         const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
