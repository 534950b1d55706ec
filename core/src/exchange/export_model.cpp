#include "thermodec/exchange/export_model.h"

#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/exchange/exported_network.h"

namespace thermodec {

namespace fs = std::filesystem;

void check_export_outputs(const ExportFormat& format, const fs::path& out, const std::string& stem,
                          const std::vector<fs::path>& protected_inputs) {
  if (out.empty()) throw InvalidInput("export: the output path is empty");
  std::error_code ec;
  const bool folder = fs::is_directory(out, ec);
  if (format.output == ExportOutput::folder && fs::exists(out, ec) && !folder)
    throw InvalidInput("export " + format.name + ": " + out.string() +
                       " is a file; the output must be a folder (created if missing)");
  if (format.output == ExportOutput::file && folder)
    throw InvalidInput("export: " + out.string() + " is a folder, not a file");
  // Known extension, not a device or FIFO, a writable folder: all before the simulation.
  const std::vector<std::string> extensions =
      format.only_these_extensions ? format.extensions : std::vector<std::string>{};
  for (const fs::path& o : export_output_files(format, out, stem)) {
    if (fs::is_directory(o, ec)) throw InvalidInput("export: " + o.string() + " is a folder, not a file");
    for (const fs::path& in : protected_inputs)
      if (same_file(in, o)) throw InvalidInput("export: output " + o.string() + " would overwrite the input " + in.string());
    check_output_file(o, "export: output", extensions, protected_inputs);
  }
}

std::vector<fs::path> export_model(ThermalModel model, const std::string& format_name, const fs::path& out,
                                   const std::string& stem, const ExportSettings& s) {
  const ExportFormat& format = export_format(format_name);
  check_export_outputs(format, out, stem, s.protected_inputs);
  if (!format.needs_simulation) return format.write(out, {model, nullptr, stem, s.protected_inputs});
  // The simulation every front end's "simulate" runs (noise targeting, then the chain).
  const FrontEndSimulation sim = simulate_as_front_end(model, s.simulation, s.noise);
  const ExportedNetwork network = exported_network(model, sim.couplings, sim.result, s.title);
  return format.write(out, {model, &network, stem, s.protected_inputs});
}

}  // namespace thermodec
