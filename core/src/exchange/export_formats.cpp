#include "thermodec/exchange/export_formats.h"

#include <algorithm>

#include "thermodec/common/errors.h"
#include "thermodec/exchange/write_csv_tables.h"
#include "thermodec/exchange/write_esatan_network.h"
#include "thermodec/exchange/write_nastran_bulk.h"
#include "thermodec/exchange/write_sinda_network.h"
#include "thermodec/exchange/write_vtk_series.h"

namespace thermodec {
namespace {

namespace fs = std::filesystem;
using Paths = std::vector<fs::path>;

fs::path csv_prefix(const fs::path& out) { return out.extension() == ".csv" ? fs::path(out).replace_extension() : out; }

// The table. A row: name, title, extensions (first = default), only those extensions, output
// kind, needs the simulation, help, writer, output files (null = the one file `out`). New rows
// go at the end: MeshLab .mlx scripts store the menu index of the format.
std::vector<ExportFormat> built_in_formats() {
  return {
      {"nastran", "NASTRAN bulk data", {".bdf", ".nas", ".dat"}, true, ExportOutput::file, false,
       "NASTRAN bulk data (.bdf): GRID* (large-field, m), CTRIA3 per face, one PSHELL per thermal\n"
       "node (name in a '$ thermodec node' comment), RADM alpha/eps per material. For Thermal\n"
       "Desktop's FE importer, ESA TASverter, Simcenter, FreeCAD FEM. No simulation needed.",
       [](const fs::path& out, const ExportInput& in) {
         write_nastran_bulk(out, in.model, in.protected_inputs);
         return Paths{out};
       },
       nullptr},
      {"esatan", "ESATAN-TMS network", {".d"}, false, ExportOutput::file, true,
       "ESATAN-TMS network (.d): $NODES (label, T, C, A, ALP, EPS, QI), $CONDUCTORS GL [W/K] and\n"
       "GR [m^2], orbit loads per node as cyclic $ARRAYS tables, $EXECUTION SOLVFM (+ SLCRNC).",
       [](const fs::path& out, const ExportInput& in) {
         write_esatan_network(out, *in.network, in.protected_inputs);
         return Paths{out};
       },
       nullptr},
      {"sinda", "SINDA/FLUINT network", {".inp"}, false, ExportOutput::file, true,
       "SINDA/FLUINT input (.inp): HEADER NODE/CONDUCTOR (radiation conductors with '-' ids)/\n"
       "ARRAY/CONTROL/VARIABLES 1/OPERATIONS DATA, as Thermal Desktop writes them.",
       [](const fs::path& out, const ExportInput& in) {
         write_sinda_network(out, *in.network, in.protected_inputs);
         return Paths{out};
       },
       nullptr},
      {"vtk", "ParaView series", {".pvd", ".vtu"}, false, ExportOutput::folder, true,
       "ParaView series: the output is a folder; one .vtu per orbit step (cells: node_id, material_id,\n"
       "area_m2, temperature_K, absorbed_flux_W_per_m2) and <model>.pvd indexing them by time.",
       [](const fs::path& out, const ExportInput& in) {
         return Paths{write_vtk_series(out, in.stem, in.model, *in.network, in.protected_inputs)};
       },
       [](const fs::path& out, const std::string& stem) { return Paths{out / (stem + ".pvd")}; }},
      {"csv", "CSV tables", {".csv"}, false, ExportOutput::prefix, true,
       "CSV tables; the output is a prefix P: P_temperatures.csv (K vs s), P_couplings.csv (GL W/K,\n"
       "GR m^2), P_loads.csv (W per node and time), P_nodes.csv (node data, period).",
       [](const fs::path& out, const ExportInput& in) {
         return write_csv_tables(csv_prefix(out), *in.network, in.protected_inputs);
       },
       [](const fs::path& out, const std::string&) {
         const std::string p = csv_prefix(out).string();
         return Paths{p + "_temperatures.csv", p + "_couplings.csv", p + "_loads.csv", p + "_nodes.csv"};
       }},
  };
}

std::vector<ExportFormat>& table() {
  static std::vector<ExportFormat> formats = built_in_formats();
  return formats;
}

bool valid_name(const std::string& name) {
  return !name.empty() &&
         std::all_of(name.begin(), name.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); });
}

}  // namespace

const std::vector<ExportFormat>& export_formats() { return table(); }

const ExportFormat& export_format(const std::string& name) {
  for (const ExportFormat& f : table())
    if (f.name == name) return f;
  throw InvalidInput("unknown export format '" + name + "' (expected " + export_format_choices() + ")");
}

std::vector<std::string> export_format_names() {
  std::vector<std::string> names;
  for (const ExportFormat& f : table()) names.push_back(f.name);
  return names;
}

std::string export_format_choices() {
  const std::vector<std::string> names = export_format_names();
  std::string text;
  for (size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

void add_export_format(ExportFormat format) {
  if (!valid_name(format.name))
    throw InvalidInput("export format name '" + format.name + "': lower-case letters and digits only");
  for (const ExportFormat& f : table())
    if (f.name == format.name) throw InvalidInput("export format '" + format.name + "' exists already");
  if (!format.write) throw InvalidInput("export format '" + format.name + "' has no writer");
  if (format.output == ExportOutput::file && format.extensions.empty())
    throw InvalidInput("export format '" + format.name + "' writes a file but names no extension");
  table().push_back(std::move(format));
}

std::vector<fs::path> export_output_files(const ExportFormat& format, const fs::path& out, const std::string& stem) {
  return format.output_files ? format.output_files(out, stem) : Paths{out};
}

fs::path default_export_output(const ExportFormat& format, const fs::path& base) {
  switch (format.output) {
    case ExportOutput::file: return base.string() + (format.extensions.empty() ? "" : format.extensions.front());
    case ExportOutput::folder: return base.string() + "_" + format.name;
    case ExportOutput::prefix: break;
  }
  return base;
}

}  // namespace thermodec
