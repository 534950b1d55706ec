#pragma once
//! ParaView-ready results: one VTK XML unstructured grid (.vtu, ASCII) per time step with the
//! surface mesh [m] and per-face cell data (node_id, material_id, area_m2, temperature_K,
//! absorbed_flux_W_per_m2: the node's absorbed external load over its radiating area), field
//! data with the node and material names, and a .pvd collection indexing the steps by time [s].
#include <filesystem>
#include <string>
#include <vector>

#include "thermodec/exchange/exported_network.h"

namespace thermodec {

//! Writes `<dir>/<stem>_NNNN.vtu` per time step and `<dir>/<stem>.pvd`, each atomically.
//! Returns the .pvd path. \throw InvalidInput on a mesh/network size mismatch or a protected
//! path; IOError on write failure.
std::filesystem::path write_vtk_series(const std::filesystem::path& dir, const std::string& stem,
                                       const ThermalModel& model, const ExportedNetwork& network,
                                       const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
