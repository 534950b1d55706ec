#pragma once
//! One call for every exchange format, shared by the CLI (`thermodec export`), the Python module
//! and the FreeCAD workbench: the NASTRAN mesh as is; the network and result formats after the
//! same simulation `thermodec simulate` runs (bare-mesh ray budgets, noise-targeted sampling).
#include <filesystem>
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

enum class ExchangeFormat { nastran, esatan, sinda, vtk, csv };

//! "nastran" "esatan" "sinda" "vtk" "csv". \throw InvalidInput naming the choices otherwise.
ExchangeFormat exchange_format(const std::string& name);

struct ExportSettings {
  ModelSimulationSettings simulation;  //!< progress messages go through simulation.progress
  //! Noise-targeted sampling as in `simulate` (thermal/simulate_model.h); target_K 0 = off.
  NoiseTargeting noise;
  std::string title;                   //!< written in the files' header comments
  std::vector<std::filesystem::path> protected_inputs;  //!< never overwritten
};

//! The output files `export_model` writes for `out` (vtk: the .pvd inside the folder `out`,
//! named after `stem`; csv: `out` without a .csv extension as the prefix of three tables).
std::vector<std::filesystem::path> export_outputs(ExchangeFormat format, const std::filesystem::path& out,
                                                  const std::string& stem);

//! Writes `model` in `format` at `out` and returns the files written. `model` is taken as
//! loaded (its ray settings, boosts); `stem` names the VTK series.
//! \throw InvalidInput if an output is a protected input or of the wrong kind (a folder where
//! a file goes, or the reverse), checked before the simulation; errors of the simulation.
std::vector<std::filesystem::path> export_model(ThermalModel model, ExchangeFormat format,
                                                const std::filesystem::path& out, const std::string& stem,
                                                const ExportSettings& settings = {});

}  // namespace thermodec
