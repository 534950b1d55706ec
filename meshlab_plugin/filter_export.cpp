// "Thermal: export for other tools": the document's thermal model written by the core's exchange
// export (core/include/thermodec/exchange/export_model.h) in one of the formats of the core's
// table (exchange/export_formats.h), exactly as `thermodec export` writes a model file. The
// filter only reads its parameters, picks the default output path and logs what was written.
#include <algorithm>
#include <string>
#include <vector>

#include <QDir>
#include <QFileInfo>
#include <QStringList>

#include "filter_thermodec.h"
#include "export_calls.h"
#include "thermodec/common/errors.h"
#ifdef THERMODEC_FILTER_EXPORT
#include "document_mesh.h"
#include "filter_support.h"
#endif

namespace {

// The core's table of export formats (exchange/export_formats.h) in menu order: the format
// parameter's choices, their tooltips and the default output names all come from it.
std::vector<thermodec_meshlab::ExportFormatRow> format_rows() {
#ifdef THERMODEC_FILTER_EXPORT
  return thermodec_meshlab::export_format_rows();
#else
  return {};
#endif
}

inline void progress(vcg::CallBackPos* cb, int percent, const char* what) {
  if (cb != nullptr) cb(percent, what);
}

}  // namespace

QString ThermodecFilterPlugin::export_info() const {
  QString formats, without_simulation;
  for (const auto& f : format_rows()) {
    formats += QString("<b>%1</b> %2; ").arg(QString::fromStdString(f.name), QString::fromStdString(f.title));
    if (!f.needs_simulation) without_simulation += QString(" %1").arg(QString::fromStdString(f.name));
  }
  return "Writes the thermal model of the document for other thermal tools, as <code>thermodec "
         "export</code> does (docs/exchange.md): " + formats +
         "the formats that carry results first simulate the model as <i>Thermal: simulate</i> does "
         "(not needed:" + without_simulation + "). Materials, node data, environment and "
         "analysis come from the optional model file, else the core defaults. The output defaults "
         "to a file, a folder or a file prefix, as the format writes one or several files, beside "
         "the current layer's file and named after it; the files written go to the log. The "
         "document is not changed."
         "<br>Nodes: with one layer, its face quality holds node ids (see <i>Thermal: assign "
         "nodes</i>); with several layers, every layer is one node (the one-file-per-node "
         "layout, e.g. an .mlp project).";
}

void ThermodecFilterPlugin::export_parameters(MeshModel& m, RichParameterList& params) const {
  QStringList formats;
  QString tooltip;
  for (const auto& f : format_rows()) {
    formats << QString::fromStdString(f.name);
    tooltip += QString::fromStdString(f.name + ": " + f.help + "\n");
  }
  params.addParam(RichEnum("format", 0, formats, "Format", tooltip.trimmed()));
  params.addParam(RichString("output", "", "Output",
                             "The file to write, or the folder or file prefix of a format that writes "
                             "several files (see Format). Empty: beside the current layer's file, "
                             "named after it."));
  thermodec_meshlab::add_model_file_parameter(params, m,
                           "thermodec model file giving materials, node capacitances and powers, "
                           "conductances, environment, analysis and radiation settings (found and matched "
                           "as in Thermal: simulate). Empty and none found: the core defaults.");
  params.addParam(RichInt("rays_per_face", 0, "Rays per face",
                          "Monte Carlo rays per face for the radiative couplings; 0 = the model's "
                          "setting. Not used by formats that need no simulation."));
  params.addParam(RichFloat("noise_target_K", 0.0025f, "Noise target [K]",
                            "Noise-targeted sampling as `thermodec export --noise-target` (0 = off): "
                            "extra rays for the nodes whose temperature noise exceeds it."));
}

bool ThermodecFilterPlugin::export_for_tools(MeshDocument& md, const RichParameterList& params,
                                             vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_EXPORT
  using namespace thermodec_meshlab;
  const std::vector<ExportFormatRow> rows = format_rows();
  const int choice = params.getEnum("format");
  if (choice < 0 || choice >= int(rows.size())) throw thermodec::InvalidInput("unknown export format");
  const QString format = QString::fromStdString(rows[choice].name);
  if (params.getInt("rays_per_face") < 0)
    throw thermodec::InvalidInput("rays_per_face must be >= 0 (0 = the model's)");
  if (params.getFloat("noise_target_K") < 0.0f)
    throw thermodec::InvalidInput("noise_target_K must be >= 0 (0 = off)");
  if (md.mm() == nullptr) throw thermodec::InvalidInput("the document has no mesh layer");

  QString out = text_parameter(params, "output");
  const QFileInfo layer_file(thermodec_meshlab::layer_file(*md.mm()));
  if (out.isEmpty()) {
    if (layer_file.filePath().isEmpty() || !layer_file.dir().exists())
      throw thermodec::InvalidInput("output: the current layer has no file to put the export beside; set output");
    // Beside the layer's file, named after it: <stem>.bdf, <stem>.d, the folder <stem>_vtk, ...
    out = QString::fromStdString(default_export_path(
        format.toStdString(), layer_file.dir().filePath(layer_file.completeBaseName()).toStdString()));
  }
  out = QDir(out).absolutePath();

  progress(cb, 0, "Thermal: gathering nodes");
  const DocumentMesh dm = mesh_with_nodes(md);
  DocumentModelRequest request;
  request.mesh = &dm.mesh;
  request.node_ids = dm.node_ids;
  request.ids_index_model_nodes = dm.source == NodeSource::FaceQuality;
  const ModelFileChoice model = choose_model_file(params, dm.layer != nullptr ? *dm.layer : *md.mm());
  request.model_file = model.path.toStdString();
  Log(model.path.isEmpty() ? GLLogStream::WARNING : GLLogStream::FILTER, "Thermal: export for other tools: %s",
      model.path.isEmpty() ? "no model file given or found beside the mesh: thermodec's defaults for a bare mesh"
                           : qUtf8Printable(model.path + " (" + model.how + ")"));
  request.rays_per_face = params.getInt("rays_per_face");
  DocumentExport what;
  what.format = format.toStdString();
  what.out = out.toStdString();
  what.stem = layer_file.completeBaseName().isEmpty() ? "model" : layer_file.completeBaseName().toStdString();
  // The dialog's single-precision value as the decimal it shows (0.0025, not 0.00249999994):
  // the same target as `thermodec export`, so the same samples.
  what.noise_target_K = QString::number(params.getFloat("noise_target_K"), 'g', 7).toDouble();
  std::vector<std::string> files;
  const StageOf stages = simulation_chain_stages();
  run_with_progress(
      cb, stages,
      [&](const std::function<void(const std::string&)>& report) {
        request.progress = report;
        files = export_document(request, what);
      },
      [this](const std::string& m) { Log("  %s", m.c_str()); });

  Log("Thermal: export for other tools (%s, %d faces, %d nodes): %s", qUtf8Printable(format),
      dm.mesh.num_faces(), int(dm.mesh.node_names.size()), qUtf8Printable(out));
  for (const std::string& f : files) Log("  wrote %s", f.c_str());
  progress(cb, 100, "Thermal: exported");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no exchange export");
#endif
}
