#include "thermodec/exchange/export_model.h"

#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/exchange/exported_network.h"
#include "thermodec/exchange/write_csv_tables.h"
#include "thermodec/exchange/write_esatan_network.h"
#include "thermodec/exchange/write_nastran_bulk.h"
#include "thermodec/exchange/write_sinda_network.h"
#include "thermodec/exchange/write_vtk_series.h"

namespace thermodec {
namespace {

namespace fs = std::filesystem;

fs::path csv_prefix(const fs::path& out) { return out.extension() == ".csv" ? fs::path(out).replace_extension() : out; }

// Refuses, before any work, an output onto an input or of the wrong kind.
void check_outputs(ExchangeFormat format, const fs::path& out, const std::string& stem, const ExportSettings& s) {
  if (out.empty()) throw InvalidInput("export: the output path is empty");
  std::error_code ec;
  const bool folder = fs::is_directory(out, ec);
  if (format == ExchangeFormat::vtk && fs::exists(out, ec) && !folder)
    throw InvalidInput("export vtk: " + out.string() + " is a file; the output must be a folder (created if missing)");
  if (format != ExchangeFormat::vtk && format != ExchangeFormat::csv && folder)
    throw InvalidInput("export: " + out.string() + " is a folder, not a file");
  // Known extension, not a device or FIFO, a writable folder: all before the simulation.
  const std::vector<std::string> extensions =
      format == ExchangeFormat::nastran ? std::vector<std::string>{".bdf", ".nas", ".dat"} : std::vector<std::string>{};
  for (const fs::path& o : export_outputs(format, out, stem)) {
    if (fs::is_directory(o, ec)) throw InvalidInput("export: " + o.string() + " is a folder, not a file");
    for (const fs::path& in : s.protected_inputs)
      if (same_file(in, o)) throw InvalidInput("export: output " + o.string() + " would overwrite the input " + in.string());
    check_output_file(o, "export: output", extensions, s.protected_inputs);
  }
}

}  // namespace

ExchangeFormat exchange_format(const std::string& name) {
  if (name == "nastran") return ExchangeFormat::nastran;
  if (name == "esatan") return ExchangeFormat::esatan;
  if (name == "sinda") return ExchangeFormat::sinda;
  if (name == "vtk") return ExchangeFormat::vtk;
  if (name == "csv") return ExchangeFormat::csv;
  throw InvalidInput("unknown export format '" + name + "' (expected nastran, esatan, sinda, vtk or csv)");
}

std::vector<fs::path> export_outputs(ExchangeFormat format, const fs::path& out, const std::string& stem) {
  if (format == ExchangeFormat::vtk) return {out / (stem + ".pvd")};
  if (format == ExchangeFormat::csv) {
    const std::string p = csv_prefix(out).string();
    return {p + "_temperatures.csv", p + "_couplings.csv", p + "_loads.csv", p + "_nodes.csv"};
  }
  return {out};
}

std::vector<fs::path> export_model(ThermalModel model, ExchangeFormat format, const fs::path& out,
                                   const std::string& stem, const ExportSettings& s) {
  check_outputs(format, out, stem, s);
  if (format == ExchangeFormat::nastran) {
    write_nastran_bulk(out, model, s.protected_inputs);
    return {out};
  }
  // The simulation every front end's "simulate" runs (noise targeting, then the chain).
  const FrontEndSimulation sim = simulate_as_front_end(model, s.simulation, s.noise);
  const NodeCouplings& couplings = sim.couplings;
  const SimulationResult& result = sim.result;
  const ExportedNetwork network = exported_network(model, couplings, result, s.title);
  switch (format) {
    case ExchangeFormat::esatan: write_esatan_network(out, network, s.protected_inputs); return {out};
    case ExchangeFormat::sinda: write_sinda_network(out, network, s.protected_inputs); return {out};
    case ExchangeFormat::vtk: return {write_vtk_series(out, stem, model, network, s.protected_inputs)};
    case ExchangeFormat::csv: return write_csv_tables(csv_prefix(out), network, s.protected_inputs);
    case ExchangeFormat::nastran: break;
  }
  return {out};
}

}  // namespace thermodec
