#include "export_calls.h"

#include "document_model.h"
#include "thermodec/exchange/export_model.h"

namespace thermodec_meshlab {

std::vector<std::string> export_document(const DocumentModelRequest& request, const DocumentExport& what) {
  // The format is checked before the model is built: a misspelt format costs nothing.
  const thermodec::ExchangeFormat format = thermodec::exchange_format(what.format);
  std::vector<int> model_node;
  std::string description;
  thermodec::ThermalModel model =
      document_model(*request.mesh, request.node_ids, request.ids_index_model_nodes, request.model_file,
                     request.rays_per_face, model_node, description);
  thermodec::ExportSettings settings;
  settings.simulation.progress = request.progress;
  settings.noise.target_K = what.noise_target_K;
  settings.title = request.model_file.empty() ? "MeshLab document (core defaults)"
                                              : "MeshLab document with " + request.model_file;
  if (!request.model_file.empty()) settings.protected_inputs.push_back(request.model_file);
  if (!model.mesh_path.empty()) settings.protected_inputs.push_back(model.mesh_path);
  std::vector<std::string> files;
  for (const auto& f : thermodec::export_model(std::move(model), format, what.out, what.stem, settings))
    files.push_back(f.string());
  return files;
}

}  // namespace thermodec_meshlab
