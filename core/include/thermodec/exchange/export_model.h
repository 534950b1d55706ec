#pragma once
//! One call for every exchange format of the table (exchange/export_formats.h), shared by the CLI
//! (`thermodec export`), the MeshLab filter, the Python module and the FreeCAD workbench: formats
//! that need no simulation (the NASTRAN mesh) as is; the network and result formats after the same
//! simulation `thermodec simulate` runs (bare-mesh ray budgets, noise-targeted sampling).
#include <filesystem>
#include <string>
#include <vector>

#include "thermodec/exchange/export_formats.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

struct ExportSettings {
  ModelSimulationSettings simulation;  //!< progress messages go through simulation.progress
  //! Noise-targeted sampling as in `simulate` (thermal/simulate_model.h); target_K 0 = off.
  NoiseTargeting noise;
  std::string title;                   //!< written in the files' header comments
  std::vector<std::filesystem::path> protected_inputs;  //!< never overwritten
};

//! Refuses, before any work, outputs of `format` at `out` that cannot be written: a protected
//! input, a folder where a file goes or the reverse, an extension the format does not take
//! (ExportFormat::only_these_extensions; a file needs one), a device or FIFO, an unwritable folder.
//! \throw InvalidInput naming the path and what is wrong.
void check_export_outputs(const ExportFormat& format, const std::filesystem::path& out, const std::string& stem,
                          const std::vector<std::filesystem::path>& protected_inputs);

//! Writes `model` in the format named `format` (a row of export_formats()) at `out` and returns
//! the files written. `model` is taken as loaded (its ray settings, boosts); `stem` names the
//! files of folder formats (the VTK series).
//! \throw InvalidInput for an unknown format or an output check_export_outputs refuses, both
//! before the simulation; errors of the simulation and of the writer.
std::vector<std::filesystem::path> export_model(ThermalModel model, const std::string& format,
                                                const std::filesystem::path& out, const std::string& stem,
                                                const ExportSettings& settings = {});

}  // namespace thermodec
