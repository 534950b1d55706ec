#include "export_calls.h"

#include "document_model.h"
#include "thermodec/exchange/export_model.h"

namespace thermodec_meshlab {

std::vector<std::string> export_document(const DocumentModelRequest& request, const DocumentExport& what) {
  // The format is checked before the model is built: a misspelt format costs nothing.
  thermodec::export_format(what.format);
  std::vector<int> model_node;
  std::string description;
  thermodec::ThermalModel model = document_model(request, model_node, description);
  thermodec::ExportSettings settings;
  settings.simulation.progress = request.progress;
  settings.noise.target_K = what.noise_target_K;
  settings.title = request.model_file.empty() ? "MeshLab document (core defaults)"
                                              : "MeshLab document with " + request.model_file;
  if (!request.model_file.empty()) settings.protected_inputs.push_back(request.model_file);
  if (!model.mesh_path.empty()) settings.protected_inputs.push_back(model.mesh_path);
  if (thermodec::export_format(what.format).needs_simulation)
    refuse_costly(thermodec::check_front_end_simulation_cost(model, settings.simulation, settings.noise));
  std::vector<std::string> files;
  for (const auto& f : thermodec::export_model(std::move(model), what.format, what.out, what.stem, settings))
    files.push_back(f.string());
  return files;
}

std::vector<ExportFormatRow> export_format_rows() {
  std::vector<ExportFormatRow> rows;
  for (const thermodec::ExportFormat& f : thermodec::export_formats()) {
    std::string help = f.help;
    for (char& c : help)
      if (c == '\n') c = ' ';
    rows.push_back({f.name, f.title, help, f.needs_simulation});
  }
  return rows;
}

std::string default_export_path(const std::string& format, const std::string& base) {
  return thermodec::default_export_output(thermodec::export_format(format), base).string();
}

}  // namespace thermodec_meshlab
