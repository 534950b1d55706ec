#pragma once
//! The table of export formats that every front end reads: `thermodec export` (its `--format`
//! choices and help), export_model, the MeshLab filter (menu, default output names), the FreeCAD
//! workbench (format list, file-dialog filters) and the Python module (`export_formats()`).
//! A new format is one writer (its own file, as write_esatan_network.h) and one row of the table
//! in export_formats.cpp; add_export_format adds a row at run time (tests, embedding programs).
//! New rows go at the end: MeshLab's .mlx scripts record the format menu's index.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "thermodec/exchange/exported_network.h"
#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

//! What the output path of a format names.
enum class ExportOutput {
  file,    //!< one file (nastran, esatan, sinda)
  folder,  //!< a folder the writer fills (vtk), created if missing
  prefix,  //!< the prefix of several files (csv: `<prefix>_temperatures.csv`, ...)
};

//! What a writer receives besides its output path.
struct ExportInput {
  const ThermalModel& model;               //!< as loaded (ray settings, boosts)
  const ExportedNetwork* network;          //!< the simulated network; null when !needs_simulation
  const std::string& stem;                 //!< names the files of folder formats (`<stem>.pvd`)
  const std::vector<std::filesystem::path>& protected_inputs;  //!< never overwritten
};

//! Writes one format at `out` and returns the files written.
//! \throw InvalidInput on a protected path or bad data; IOError on write failure.
using ExportWriter = std::function<std::vector<std::filesystem::path>(const std::filesystem::path& out,
                                                                      const ExportInput& input)>;

//! The files a writer will write for `out` and `stem` (checked before any work).
using ExportOutputFiles =
    std::function<std::vector<std::filesystem::path>(const std::filesystem::path& out, const std::string& stem)>;

//! One row of the table.
struct ExportFormat {
  std::string name;                     //!< `--format` value, lower case ("esatan")
  std::string title;                    //!< menus and file dialogs ("ESATAN-TMS network")
  std::vector<std::string> extensions;  //!< lower case with the dot, the first the default (".d")
  bool only_these_extensions = false;   //!< file outputs: refuse other extensions (else any)
  ExportOutput output = ExportOutput::file;
  bool needs_simulation = true;         //!< false: written from the model alone (no rays)
  std::string help;                     //!< a few lines for `--help` and tooltips, '\n'-separated
  ExportWriter write;                   //!< the writer
  ExportOutputFiles output_files;       //!< null: `{out}` (one file)
};

//! Every format, in menu order: nastran, esatan, sinda, vtk, csv, then any added ones.
const std::vector<ExportFormat>& export_formats();

//! The row named `name`. \throw InvalidInput naming the choices if there is none.
const ExportFormat& export_format(const std::string& name);

//! The names in table order, and as words for messages ("nastran, esatan, sinda, vtk or csv").
std::vector<std::string> export_format_names();
std::string export_format_choices();

//! Appends `format` to the table. Call before the table is read from other threads (at the
//! start of a program or test): references from export_formats() may be invalidated.
//! \throw InvalidInput if the name is empty, not lower-case letters/digits or taken, the writer
//! is missing, or a file format has no extension.
void add_export_format(ExportFormat format);

//! The files `format` writes for `out` (ExportFormat::output_files, else `{out}`).
std::vector<std::filesystem::path> export_output_files(const ExportFormat& format, const std::filesystem::path& out,
                                                       const std::string& stem);

//! The default output for a model at `base` (a path without extension, e.g. `dir/model`):
//! `base` + the first extension for a file, `base_<name>` for a folder, `base` for a prefix.
std::filesystem::path default_export_output(const ExportFormat& format, const std::filesystem::path& base);

}  // namespace thermodec
