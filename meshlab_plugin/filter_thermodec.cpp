#include "filter_thermodec.h"

#include <algorithm>
#include <exception>
#include <map>
#include <string>
#include <vector>

#include <QDir>
#include <QFileInfo>

#include "document_mesh.h"
#include "filter_support.h"
#include "thermodec/common/errors.h"
#ifdef THERMODEC_FILTER_ASSIGN_NODES
#include "thermodec/nodes/automatic_nodes.h"
#endif
#ifdef THERMODEC_FILTER_EXTRACT_EXTERNAL
#include "thermodec/radiation/external_geometry.h"
#include "thermodec/rays/ray_scene.h"
#endif
#ifdef THERMODEC_FILTER_DECIMATE_RATIO
#include "thermodec/decimation/decimate_nodes.h"
#endif
#if defined(THERMODEC_FILTER_SIMULATE) || defined(THERMODEC_FILTER_REDUCE)
#include <vcg/complex/algorithms/update/color.h>

#include "core_calls.h"
#endif

using namespace thermodec_meshlab;

namespace {

// How every Thermal filter finds the nodes (document_mesh.h, mesh_with_nodes).
const char* const kNodesHelp =
    "<br>Nodes: the current layer's face quality holds node ids (see <i>Thermal: assign nodes</i>; "
    "a PLY written by <code>thermodec convert</code> also names them in its header), or, for a "
    "layer a Thermal filter made, the ids it keeps; without ids, every layer is one node (the "
    "one-file-per-node layout, e.g. an .mlp project). Layers made by Thermal filters are never "
    "taken for nodes, so the filters run in any order.";

// MeshLab's progress callback may be null (scripted calls); never dereference it blindly.
inline void progress(vcg::CallBackPos* cb, int percent, const char* what) {
  if (cb != nullptr) cb(percent, what);
}

}  // namespace

ThermodecFilterPlugin::ThermodecFilterPlugin() {
#ifdef THERMODEC_FILTER_ASSIGN_NODES
  typeList << FP_ASSIGN_NODES;
#endif
#ifdef THERMODEC_FILTER_EXTRACT_EXTERNAL
  typeList << FP_EXTRACT_EXTERNAL;
#endif
#ifdef THERMODEC_FILTER_DECIMATE_RATIO
  typeList << FP_DECIMATE_RATIO;
#endif
#ifdef THERMODEC_FILTER_SIMULATE
  typeList << FP_SIMULATE;
#endif
#ifdef THERMODEC_FILTER_REDUCE
  typeList << FP_SENSITIVITY << FP_REDUCE;
#endif
#ifdef THERMODEC_FILTER_EXPORT
  typeList << FP_EXPORT;
#endif
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString ThermodecFilterPlugin::pluginName() const { return "FilterThermodec"; }

QString ThermodecFilterPlugin::filterName(FilterIDType filter) const {
  switch (filter) {
    case FP_ASSIGN_NODES: return "Thermal: assign nodes";
    case FP_EXTRACT_EXTERNAL: return "Thermal: extract external geometry";
    case FP_DECIMATE_RATIO: return "Thermal: decimate to global ratio";
    case FP_SIMULATE: return "Thermal: simulate";
    case FP_SENSITIVITY: return "Thermal: sensitivity analysis";
    case FP_REDUCE: return "Thermal: physics-informed decimation";
    case FP_EXPORT: return "Thermal: export for other tools";
  }
  assert(false);
  return QString();
}

QString ThermodecFilterPlugin::filterInfo(FilterIDType filter) const {
  switch (filter) {
    case FP_ASSIGN_NODES:
      return "Automatic nodal breakdown of the current layer for thermal analysis (thermodec): "
             "connected components, split into near-planar regions by normal deviation, small "
             "regions merged into their neighbours, the node count capped.<br>"
             "Every face gets a node: its id (0, 1, ...) is written to the <b>face quality</b> "
             "and the face is painted with one colour per node. Save with face quality "
             "(meshlabserver <code>-m fq</code>) to keep the nodes; the other Thermal filters "
             "read them from there. Deterministic: the same mesh always gives the same nodes.";
    case FP_EXTRACT_EXTERNAL:
      return "Keeps the faces visible from outside the spacecraft (thermodec external-geometry "
             "extraction: a face is kept if a ray leaving it escapes to infinity) and drops "
             "internal ones, e.g. walls hidden inside closed solids. The result is added as new "
             "layer(s) named '... external'; kept/dropped faces per node go to the log. Works "
             "with or without nodes." + QString(kNodesHelp);
    case FP_DECIMATE_RATIO:
      return "Node-preserving decimation of the thermal model's shared mesh (thermodec): removes "
             "the given fraction of all faces, spread over the nodes by the paper's global-ratio "
             "rule, without ever moving a face to another node, opening holes or changing any "
             "node's area or closed volume beyond the stated tolerances. The result is added as "
             "new layer(s) named '... decimated'; faces per node before/after go to the log. "
             "(To reduce as far as a temperature tolerance allows, use <i>Thermal: "
             "physics-informed decimation</i>.)" + QString(kNodesHelp);
    case FP_SENSITIVITY:
      return "The paper's per-node sensitivity analysis (thermodec): each node alone is "
             "decimated by increasing ratios, the rest of the model unchanged, and the largest "
             "temperature difference of the whole model over the orbit is recorded, until it "
             "exceeds twice the tolerance. Curves are written as sensitivity.csv and "
             "sensitivity.png in the output folder (default: beside the current layer's file); "
             "a summary per node goes to the log. Simulation settings as in <i>Thermal: "
             "simulate</i>." + QString(kNodesHelp);
    case FP_REDUCE:
      // Kept short: MeshLab 2020.09 sizes the dialog before the wrapped text, and a longer
      // text pushes the last field under the buttons (strategies: the Strategy field's help).
      return "Simulation-driven reduction (thermodec reduce, paper IV-V): decimates every node as "
             "far as the temperature tolerance allows, verified by a full re-simulation (max |dT| "
             "over all nodes and the orbit <= tolerance). New layer(s) '... reduced'; model.json + "
             "reduced.obj, report.json and plots in the output folder (default: beside the current "
             "layer's file); the summary in the log. Simulation settings as in <i>Thermal: "
             "simulate</i>." + QString(kNodesHelp);
    case FP_EXPORT: return export_info();
    case FP_SIMULATE:
      return "Radiative thermal simulation of the nodes, the same as <code>thermodec simulate</code> "
             "(Monte Carlo radiative couplings, orbit or fixed-sun loads, steady or orbit-periodic "
             "transient solve, noise-targeted sampling): the same model and seed give the same "
             "temperatures. The result is a new layer '&lt;layer&gt; temperature &lt;min&gt; to "
             "&lt;max&gt; K' whose face quality holds the chosen statistic [K] with a colour ramp "
             "(blue cold, red hot); the input layer is hidden. Per-node min/mean/max [K] and the "
             "range go to the log. Materials, environment and analysis come from the model file "
             "(chosen, else the one used last with the layer, else a model JSON beside the mesh "
             "naming a mesh of the same name); without one, the defaults used are stated in the log."+ QString(kNodesHelp);
  }
  assert(false);
  return QString();
}

// Every Thermal filter in one submenu (Filters > Quality Measure and Computations): the class
// only places the menu entry; what the GUI refreshes after a filter is its postCondition.
MeshFilterInterface::FilterClass ThermodecFilterPlugin::getClass(QAction* /*action*/) { return Measure; }

MeshFilterInterface::FILTER_ARITY ThermodecFilterPlugin::filterArity(QAction* action) const {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return SINGLE_MESH;
    // These read every layer of a multi-layer document (one layer = one node).
    case FP_EXTRACT_EXTERNAL:
    case FP_DECIMATE_RATIO:
    case FP_SIMULATE:
    case FP_SENSITIVITY:
    case FP_REDUCE:
    case FP_EXPORT: return VARIABLE;
  }
  assert(false);
  return SINGLE_MESH;
}

int ThermodecFilterPlugin::getRequirements(QAction* action) {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR;
    // Node ids are read from face quality only when the layer already has it: requiring it
    // here would make MeshLab add a zero quality to every layer.
    case FP_EXTRACT_EXTERNAL:
    case FP_DECIMATE_RATIO:
    case FP_SIMULATE:
    case FP_SENSITIVITY:
    case FP_REDUCE:
    case FP_EXPORT: return MeshModel::MM_NONE;
  }
  assert(false);
  return MeshModel::MM_NONE;
}

int ThermodecFilterPlugin::getPreConditions(QAction* action) const {
  switch (ID(action)) {
    case FP_ASSIGN_NODES:
    case FP_EXTRACT_EXTERNAL:
    case FP_DECIMATE_RATIO:
    case FP_SIMULATE:
    case FP_SENSITIVITY:
    case FP_REDUCE:
    case FP_EXPORT: return MeshModel::MM_FACENUMBER;
  }
  assert(false);
  return MeshModel::MM_NONE;
}

int ThermodecFilterPlugin::postCondition(QAction* action) const {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR;
    case FP_EXTRACT_EXTERNAL:
    case FP_DECIMATE_RATIO: return MeshModel::MM_NONE;  // results are new layers
    case FP_SIMULATE: return MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR;
    case FP_SENSITIVITY: return MeshModel::MM_NONE;  // files and log only
    case FP_REDUCE: return MeshModel::MM_NONE;       // results are new layers
    case FP_EXPORT: return MeshModel::MM_NONE;       // files and log only
  }
  assert(false);
  return MeshModel::MM_NONE;
}

void ThermodecFilterPlugin::initParameterSet(QAction* action, MeshModel& m,
                                             RichParameterList& params) {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: {
#ifdef THERMODEC_FILTER_ASSIGN_NODES
      const thermodec::AutomaticNodeOptions defaults;
      params.addParam(RichFloat(
          "max_normal_deviation_deg", float(defaults.max_normal_deviation_deg),
          "Max normal deviation [deg]",
          "Region growing: a face joins a node while its normal deviates from the node's seed "
          "normal by at most this angle (degrees, in (0, 180]). Smaller = more, flatter nodes."));
      params.addParam(RichFloat(
          "min_node_area_fraction", float(defaults.min_node_area_fraction),
          "Min node area fraction",
          "Regions whose area is below this fraction of the total surface area (in [0, 1)) are "
          "merged into a neighbouring node."));
      params.addParam(RichInt(
          "max_nodes", defaults.max_nodes, "Max nodes",
          "Upper bound on the number of nodes (>= 1); the smallest regions are merged first."));
#endif
      break;
    }
    case FP_EXTRACT_EXTERNAL: {
#ifdef THERMODEC_FILTER_EXTRACT_EXTERNAL
      const thermodec::ExternalSettings defaults;
      params.addParam(RichInt(
          "rays_per_face", defaults.rays_per_face, "Rays per face",
          "Maximum rays per tested face side (>= 1); the test stops at the first ray that "
          "escapes. A face seen from outside through a fraction p of its hemisphere is missed "
          "with probability about (1 - p)^rays."));
      params.addParam(RichInt("seed", int(defaults.seed), "Seed",
                              "Seed of the ray directions (same seed, same result)."));
      params.addParam(RichBool(
          "both_sides", defaults.both_sides, "Test both sides",
          "Also test the back of every face, for meshes whose orientation is unreliable "
          "(e.g. STL exports). Off: a face is seen only from the side its vertices turn "
          "counter-clockwise around."));
#endif
      break;
    }
    case FP_DECIMATE_RATIO: {
#ifdef THERMODEC_FILTER_DECIMATE_RATIO
      const thermodec::DecimationOptions defaults;
      params.addParam(RichFloat(
          "global_ratio", 0.5f, "Global ratio",
          "Fraction of all faces to remove, in [0, 1) (0.5 = keep half). Spread over the nodes "
          "by the paper's rule: small nodes first, a node that cannot remove its share hands "
          "the rest to larger ones."));
      params.addParam(RichFloat(
          "max_relative_area_change", float(defaults.max_relative_area_change),
          "Max relative area change",
          "Hard bound on |area after - area before| / area before of every node."));
      params.addParam(RichFloat(
          "max_relative_volume_change", float(defaults.max_relative_volume_change),
          "Max relative volume change",
          "Hard bound on the relative change of the volume enclosed by every closed part."));
      params.addParam(RichFloat(
          "max_contour_deviation", float(defaults.max_contour_deviation),
          "Max contour deviation",
          "A vertex on a node boundary may go only if it lies within this fraction of the "
          "replacing segment's length from it (0.02 = about 2.3 degrees of kink)."));
      params.addParam(RichBool(
          "area_neutral_placement", defaults.area_neutral_placement, "Area-neutral placement",
          "Move each collapse's new vertex (by at most a tenth of the local edge length) so that "
          "its node keeps its input area: a radiating node's temperature moves by "
          "dT = -T dA / 4A, so area is what a thermal model feels. Off: volume-preserving "
          "(Lindstrom-Turk) placement only."));
#endif
      break;
    }
    case FP_SIMULATE: {
#ifdef THERMODEC_FILTER_SIMULATE
      add_model_file_parameter(
          params, m,
          "thermodec model file (docs/model-format.md) giving materials, node capacitances/powers, "
          "conductances, environment, analysis and radiation settings. Its mesh is used when the layer "
          "is that mesh (e.g. satellite.ply beside model.json); otherwise the layer's mesh replaces it, "
          "nodes matched by name (PLY header, layer label or node_&lt;id&gt;) or else by id = position "
          "in the model. Empty and none found: the core defaults (stated in the log).");
      params.addParam(RichInt(
          "rays_per_face", 0, "Rays per face",
          "Monte Carlo rays per face for the radiative couplings; 0 = the model's setting "
          "(core default 4000). Fewer rays are faster and noisier."));
      params.addParam(RichEnum(
          "face_value", 1, QStringList() << "min" << "mean" << "max", "Face value",
          "Which temperature over the orbit goes to the face quality [K]: each face shows its "
          "node's minimum, mean or maximum (steady analysis: all equal)."));
      params.addParam(RichInt("seed", -1, "Seed",
                              "Monte Carlo seed of rays and sun/Earth samples; -1 = the model's "
                              "(as <code>thermodec simulate --seed</code>)."));
      params.addParam(RichSaveFile("result_file", "", "*.json", "Result file (JSON)",
                                   "Optional: the result as <code>thermodec simulate --json</code> "
                                   "writes it (temperatures per node and time, loads, residuals)."));
#endif
      break;
    }
    case FP_EXPORT: export_parameters(m, params); break;
    case FP_SENSITIVITY:
    case FP_REDUCE: {
#ifdef THERMODEC_FILTER_REDUCE
      const bool reduce = ID(action) == FP_REDUCE;
      params.addParam(RichFloat(
          "tolerance_K", 0.5f, "Tolerance [K]",
          reduce ? "Largest temperature difference allowed between the reduced and the original "
                   "model, over all nodes and the whole orbit [K]. Must be at least twice the "
                   "Monte Carlo noise floor, which is measured first."
                 : "Temperature tolerance [K] the curves are read against: each node's sweep "
                   "stops once the difference exceeds twice this value."));
      if (reduce)
        params.addParam(RichEnum(
            "strategy", 0, QStringList() << "informed" << "uniform", "Strategy",
            "informed: per-node ratios predicted from sensitivity curves, then verified and "
            "adjusted; uniform: the same ratio for every node (the paper's baseline)."));
      add_model_file_parameter(params, m,
                               "thermodec model file: materials, capacitances, powers, conductances, "
                               "environment, analysis and radiation settings (found and matched as in "
                               "Thermal: simulate). Empty and none found: the core defaults.");
      params.addParam(RichInt(
          "rays_per_face", 0, "Rays per face",
          "Monte Carlo rays per face for the radiative couplings; 0 = the model's setting. "
          "Fewer rays are faster but raise the noise floor the tolerance must exceed."));
      params.addParam(RichString(
          "output_dir", "", "Output folder",
          html_escaped(reduce ? "Folder for model.json, reduced.obj, report.json and the plots. Empty: "
                                "'<layer file>_thermodec_reduction' beside the layer's file (for a "
                                "layer a Thermal filter made: its input's file)."
                              : "Folder for sensitivity.csv and sensitivity.png. Empty: "
                                "'<layer file>_thermodec_sensitivity' beside the layer's file (for a "
                                "layer a Thermal filter made: its input's file).")));
      if (reduce)
        params.addParam(RichString(
            "case_files", "", "Load case files",
            "Optional: further load cases the reduced model must also meet (e.g. a cold case), "
            "separated by ';'. Each is a JSON file {\"name\", \"environment\", \"analysis\"} read "
            "over the model's own (thermodec reduce --case; docs/model-format.md)."));
      if (reduce)
        params.addParam(RichBool("merge_nodes", false, "Merge nodes",
                                 "Also merge thermal nodes into isothermal nodes before decimating (thermodec "
                                 "reduce --merge-nodes): fewer nodes and interfaces, verified against the original "
                                 "through the node map in model.json; merged faces show under their first node."));
      if (reduce)
        params.addParam(RichBool("plots", true, "Write plots",
                                 "Also write the PNG plots (sensitivity, predicted vs real, "
                                 "temperatures, mesh) with matplotlib."));
#endif
      break;
    }
  }
}

bool ThermodecFilterPlugin::applyFilter(QAction* action, MeshDocument& md,
                                        const RichParameterList& params, vcg::CallBackPos* cb) {
  // Every user-caused failure in the core is a thermodec::Error with a one-line message; it
  // goes to MeshLab's error mechanism and log. Nothing may escape into the host.
  try {
    switch (ID(action)) {
      case FP_ASSIGN_NODES: return assign_nodes(md, params, cb);
      case FP_EXTRACT_EXTERNAL: return extract_external(md, params, cb);
      case FP_DECIMATE_RATIO: return decimate_ratio(md, params, cb);
      case FP_SIMULATE: return simulate(md, params, cb);
      case FP_SENSITIVITY: return sensitivity(md, params, cb);
      case FP_REDUCE: return reduce(md, params, cb);
      case FP_EXPORT: return export_for_tools(md, params, cb);
    }
    errorMessage = "unknown thermodec filter";
  } catch (const thermodec::Error& e) {
    errorMessage = QString::fromStdString(e.what());
  } catch (const std::exception& e) {
    errorMessage = QString("internal error: ") + e.what();
  }
  Log(GLLogStream::WARNING, qUtf8Printable(filterName(action) + ": " + errorMessage));
  return false;
}

bool ThermodecFilterPlugin::assign_nodes(MeshDocument& md, const RichParameterList& params,
                                         vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_ASSIGN_NODES
  if (md.mm() == nullptr) throw thermodec::InvalidInput("the document has no mesh layer");
  thermodec::AutomaticNodeOptions options;
  options.max_normal_deviation_deg = params.getFloat("max_normal_deviation_deg");
  options.min_node_area_fraction = params.getFloat("min_node_area_fraction");
  options.max_nodes = params.getInt("max_nodes");
  // Option ranges are validated by the core (one place, one message).
  progress(cb, 0, "Thermal: gathering mesh");
  DocumentMesh dm = mesh_from_layer(*md.mm());
  progress(cb, 10, "Thermal: assigning nodes");
  thermodec::assign_automatic_nodes(dm.mesh, options);
  progress(cb, 90, "Thermal: writing node ids");

  std::vector<double> node(dm.origin.size());
  for (size_t f = 0; f < node.size(); ++f) node[f] = dm.mesh.face_node[f];
  set_face_quality(dm, node);
  paint_nodes(dm);
  set_node_names(*md.mm(), {});  // new ids: names from the file's header no longer apply

  std::vector<int> faces_per_node(dm.mesh.node_names.size(), 0);
  for (size_t f = 0; f < node.size(); ++f) ++faces_per_node[dm.mesh.face_node[f]];
  Log("Thermal: assign nodes: %d nodes on %d faces of '%s' (node id in face quality)",
      int(faces_per_node.size()), dm.mesh.num_faces(), qUtf8Printable(md.mm()->label()));
  for (size_t n = 0; n < faces_per_node.size(); ++n)
    Log("  node %d: %d faces", int(n), faces_per_node[n]);
  progress(cb, 100, "Thermal: nodes assigned");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no automatic nodal breakdown");
#endif
}

bool ThermodecFilterPlugin::extract_external(MeshDocument& md, const RichParameterList& params,
                                             vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_EXTRACT_EXTERNAL
  thermodec::ExternalSettings settings;
  settings.rays_per_face = params.getInt("rays_per_face");
  settings.seed = static_cast<std::uint64_t>(params.getInt("seed"));
  settings.both_sides = params.getBool("both_sides");

  progress(cb, 0, "Thermal: gathering mesh");
  const DocumentMesh dm = mesh_with_optional_nodes(md);
  progress(cb, 10, "Thermal: building ray scene");
  const thermodec::RayScene scene(dm.mesh);
  progress(cb, 30, "Thermal: tracing escape rays");
  const thermodec::ExternalFaces ext = thermodec::external_faces(scene, settings);
  if (ext.kept == 0)
    throw thermodec::InvalidInput("no face is visible from outside (" +
                                  std::to_string(ext.untraceable) + " untraceable faces)");
  progress(cb, 90, "Thermal: adding the external layer(s)");
  const thermodec::Mesh external = thermodec::extract_external(dm.mesh, ext);
  const auto layers = add_layers(md, dm, external, "external");

  Log("Thermal: extract external geometry: kept %d of %d faces, dropped %d (%d untraceable), "
      "%lld rays, %d new layer(s)",
      ext.kept, dm.mesh.num_faces(), ext.dropped, ext.untraceable,
      static_cast<long long>(ext.rays_traced), int(layers.size()));
  for (size_t n = 0; n < dm.mesh.node_names.size(); ++n)
    Log("  %s: kept %d, dropped %d", dm.mesh.node_names[n].c_str(), ext.kept_per_node[n],
        ext.dropped_per_node[n]);
  progress(cb, 100, "Thermal: external geometry extracted");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no external-geometry extraction");
#endif
}

bool ThermodecFilterPlugin::decimate_ratio(MeshDocument& md, const RichParameterList& params,
                                           vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_DECIMATE_RATIO
  thermodec::DecimationOptions options;
  const double ratio = params.getFloat("global_ratio");
  options.max_relative_area_change = params.getFloat("max_relative_area_change");
  options.max_relative_volume_change = params.getFloat("max_relative_volume_change");
  options.max_contour_deviation = params.getFloat("max_contour_deviation");
  options.area_neutral_placement = params.getBool("area_neutral_placement");

  progress(cb, 0, "Thermal: gathering mesh");
  const DocumentMesh dm = mesh_with_optional_nodes(md);
  progress(cb, 10, "Thermal: decimating");
  const thermodec::DecimationResult r = thermodec::decimate_to_global_ratio(dm.mesh, ratio, options);
  progress(cb, 90, "Thermal: adding the decimated layer(s)");
  const auto layers = add_layers(md, dm, r.mesh, "decimated");

  Log("Thermal: decimate to global ratio %.3f: %d -> %d faces (%.1f %% removed), %d collapses, "
      "%d new layer(s)",
      ratio, dm.mesh.num_faces(), r.mesh.num_faces(),
      100.0 * (1.0 - double(r.mesh.num_faces()) / dm.mesh.num_faces()), r.collapses,
      int(layers.size()));
  for (size_t n = 0; n < r.nodes.size(); ++n) {
    const thermodec::NodeDecimationStats& s = r.nodes[n];
    const std::string name = n < dm.mesh.node_names.size() ? dm.mesh.node_names[n] : "(no node)";
    Log("  %s: %d -> %d faces (target %d%s), area change %+.3g %%", name.c_str(),
        s.faces_before, s.faces_after, s.target_faces, s.reached ? "" : ", not reached",
        100.0 * s.relative_area_change());
  }
  progress(cb, 100, "Thermal: decimated");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no decimation");
#endif
}

bool ThermodecFilterPlugin::simulate(MeshDocument& md, const RichParameterList& params,
                                     vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_SIMULATE
  const int rays = params.getInt("rays_per_face");
  const int face_value = params.getEnum("face_value");
  const int seed = params.hasParameter("seed") ? params.getInt("seed") : -1;
  const std::string result_file = text_parameter(params, "result_file").toStdString();
  if (rays < 0) throw thermodec::InvalidInput("rays_per_face must be >= 0 (0 = the model's)");

  progress(cb, 0, "Thermal: gathering nodes");
  const DocumentMesh dm = mesh_with_nodes(md);
  MeshModel& input = dm.layer != nullptr ? *dm.layer : *md.mm();
  const ModelFileChoice model = choose_model_file(params, input);
  DocumentModelRequest request;
  request.mesh = &dm.mesh;
  request.node_ids = dm.node_ids;
  request.ids_index_model_nodes = dm.source == NodeSource::FaceQuality;
  request.model_file = model.path.toStdString();
  request.rays_per_face = rays;
  request.seed = seed;
  if (!model.path.isEmpty() && model.how != "given")
    Log("Thermal: simulate: model file %s (%s)", qUtf8Printable(model.path), qUtf8Printable(model.how));
  NodeTemperatures t;
  const StageOf stages = simulation_chain_stages();
  run_with_progress(
      cb, stages,
      [&](const std::function<void(const std::string&)>& report) {
        request.progress = report;
        t = simulate_document(request, result_file);
      },
      [this](const std::string& m) { Log("  %s", m.c_str()); });
  if (model.path.isEmpty())
    Log(GLLogStream::WARNING, "%s", ("Thermal: simulate: " + t.model_description).c_str());

  Log("Thermal: simulate (%s): %s, %d time(s)%s, %d rays per face, seed %llu", t.model_description.c_str(),
      t.transient ? "orbit-periodic transient" : "steady state", t.times,
      t.transient ? qUtf8Printable(QString(", %1 orbits, periodicity residual %2 K")
                                       .arg(t.orbits).arg(t.periodicity_residual_K, 0, 'g', 3))
                  : "",
      t.rays_per_face, t.seed);
  if (!t.sampling.empty()) Log("  %s", t.sampling.c_str());
  Log("  node: min / mean / max [K], sampling noise (1 sigma) [K]");
  for (size_t n = 0; n < t.nodes.size(); ++n)
    Log("  %s%s: %.2f / %.2f / %.2f, noise %.4f", t.nodes[n].c_str(),
        t.model_nodes[n] == t.nodes[n] ? "" : (" (as " + t.model_nodes[n] + ")").c_str(),
        t.min_K[n], t.mean_K[n], t.max_K[n], t.noise_K[n]);
  if (t.transient) Log("  orbit sampling error (estimate): %.3g K", t.orbit_sampling_error_K);

  const std::vector<double>& node_value = face_value == 0 ? t.min_K : face_value == 2 ? t.max_K : t.mean_K;
  std::vector<double> value(dm.origin.size());
  for (size_t f = 0; f < value.size(); ++f) value[f] = node_value[dm.mesh.face_node[f]];
  const auto range = std::minmax_element(node_value.begin(), node_value.end());
  const double lo = *range.first, hi = *range.second > lo ? *range.second : lo + 1.0;
  // A document node and, when it differs, the model node it was simulated as.
  const auto label = [&t](size_t n) {
    return t.model_nodes[n] == t.nodes[n] ? t.nodes[n] : t.nodes[n] + " = " + t.model_nodes[n];
  };
  const std::string lo_node = label(range.first - node_value.begin());
  const std::string hi_node = label(range.second - node_value.begin());
  const char* statistic = face_value == 0 ? "min" : face_value == 2 ? "max" : "mean";

  // Node ids: the temperatures go to a new layer that keeps the ids as its own, so that the
  // input layer stays as it was. Several layers: the nodes are the layers, so their quality is
  // free to use.
  std::vector<MeshModel*> layers;
  if (dm.source == NodeSource::FaceQuality) {
    const QString suffix = QString("%1 temperature %2 to %3 K").arg(statistic).arg(lo, 0, 'f', 2).arg(*range.second, 0, 'f', 2);
    layers = add_layers(md, dm, dm.mesh, suffix);
    MeshModel* layer = layers.front();
    std::vector<int> ids(value.size());
    for (size_t f = 0; f < value.size(); ++f) {
      layer->cm.face[f].Q() = CMeshO::ScalarType(value[f]);
      ids[f] = dm.node_ids[dm.mesh.face_node[f]];
    }
    set_layer_node_ids(*layer, ids);
  } else {
    set_face_quality(dm, value);
    for (MeshModel* layer : md.meshList)
      if (!is_result_layer(*layer)) layers.push_back(layer);
  }
  for (MeshModel* layer : layers) {
    layer->updateDataMask(MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR);
    // vcg's ramp runs red -> blue from its first bound to its second: hot is red.
    vcg::tri::UpdateColor<CMeshO>::PerFaceQualityRamp(layer->cm, CMeshO::ScalarType(hi),
                                                      CMeshO::ScalarType(lo));
  }
  Log("Thermal: temperature range over the orbit: %.2f K (min, node %s) .. %.2f K (max, node %s)",
      t.min_K[t.coldest], label(t.coldest).c_str(), t.max_K[t.hottest], label(t.hottest).c_str());
  Log("  face quality = node %s temperature [K], colour ramp %.2f K (blue, node %s) .. %.2f K (red, node %s)",
      statistic, lo, lo_node.c_str(), hi, hi_node.c_str());
  if (!result_file.empty()) Log("  wrote %s", result_file.c_str());
  progress(cb, 100, "Thermal: simulated");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no thermal simulation");
#endif
}

#ifdef THERMODEC_FILTER_REDUCE
namespace {

// The output folder: the parameter, or "<layer file stem>_thermodec_<what>" beside the current
// layer's file (the paper's users keep results next to the project).
std::string output_dir(MeshDocument& md, const RichParameterList& params, const char* what) {
  const QString given = text_parameter(params, "output_dir");
  if (!given.isEmpty()) return QDir(given).absolutePath().toStdString();
  MeshModel* from = md.mm();
  QString path = layer_file(*from);
  for (MeshModel* layer : md.meshList)  // a project of node layers: the first with a file
    if (path.isEmpty() && !is_result_layer(*layer)) path = layer->fullName();
  const QFileInfo file(path);
  if (path.isEmpty() || !file.dir().exists())
    throw thermodec::InvalidInput("output_dir: no layer has a file to put the results beside; set output_dir");
  return file.dir().filePath(file.completeBaseName() + "_thermodec_" + what).toStdString();
}

// The core request of a reduction or sensitivity run, with the model file chosen.
DocumentModelRequest reduction_request(MeshDocument& md, const DocumentMesh& dm, const RichParameterList& params,
                                       ModelFileChoice& model) {
  if (params.getInt("rays_per_face") < 0)
    throw thermodec::InvalidInput("rays_per_face must be >= 0 (0 = the model's)");
  model = choose_model_file(params, dm.layer != nullptr ? *dm.layer : *md.mm());
  DocumentModelRequest request;
  request.mesh = &dm.mesh;
  request.node_ids = dm.node_ids;
  request.ids_index_model_nodes = dm.source == NodeSource::FaceQuality;
  request.model_file = model.path.toStdString();
  request.rays_per_face = params.getInt("rays_per_face");
  return request;
}

// A merged node's members for the log: all up to six, else the first five and the count of the
// rest (the node map in model.json has them all), as the core's plots list them.
std::string member_list(const std::vector<std::string>& members) {
  const std::size_t shown = members.size() > 6 ? 5 : members.size();
  std::string out;
  for (std::size_t i = 0; i < shown; ++i) out += (i ? " + " : "") + members[i];
  if (shown < members.size()) out += " \u2026 (+" + std::to_string(members.size() - shown) + " more)";
  return out;
}

// A merged reduction's layers name each merged node as the reduced model does ("wing_py+1") and
// take that model (out_dir/model.json) as theirs: Thermal: simulate on a reduced layer then
// simulates the merged network, whose node names are the layer's. With the original model the
// other members would be left without faces.
void name_merged_nodes(const DocumentMesh& dm, const std::vector<MeshModel*>& layers, const DocumentReduction& r) {
  const QString model_file = QString::fromStdString(r.model_file);
  for (MeshModel* layer : layers) set_layer_model_file(*layer, model_file);
  if (dm.source == NodeSource::Layers) {  // one layer per node: the merged node's layer renamed
    for (const auto& m : r.merged)
      for (MeshModel* layer : layers)
        if (layer->label() == result_label(QString::fromStdString(dm.mesh.node_names[m.document_node]) + " reduced"))
          layer->setLabel(result_label(QString::fromStdString(m.name) + " reduced"));
    return;
  }
  if (layers.empty()) return;
  std::map<int, std::string> names;  // document node id -> name, as the reduced model has them
  for (std::size_t n = 0; n < dm.node_ids.size(); ++n) names[dm.node_ids[n]] = dm.mesh.node_names[n];
  for (const auto& m : r.merged) {
    for (const auto& member : m.members)
      for (std::size_t n = 0; n < dm.node_ids.size(); ++n)
        if (dm.mesh.node_names[n] == member) names.erase(dm.node_ids[n]);  // no faces of its own now
    names[dm.node_ids[m.document_node]] = m.name;
  }
  set_node_names(*layers.front(), names);
}

std::string model_line(const ModelFileChoice& model) {
  if (model.path.isEmpty()) return "no model file given or found beside the mesh: thermodec's defaults for a bare mesh";
  return "model file " + model.path.toStdString() + " (" + model.how.toStdString() + ")";
}

}  // namespace
#endif

bool ThermodecFilterPlugin::sensitivity(MeshDocument& md, const RichParameterList& params,
                                        vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_REDUCE
  const double tolerance = params.getFloat("tolerance_K");
  const std::string out_dir = output_dir(md, params, "sensitivity");
  progress(cb, 0, "Thermal: gathering nodes");
  const DocumentMesh dm = mesh_with_nodes(md);
  ModelFileChoice model;
  DocumentModelRequest request = reduction_request(md, dm, params, model);
  Log(model.path.isEmpty() ? GLLogStream::WARNING : GLLogStream::FILTER,
      "%s", ("Thermal: sensitivity analysis: " + model_line(model)).c_str());
  DocumentSensitivity s;
  const StageOf stages = [](const std::string& m) -> double {
    if (m.find("reference") != std::string::npos) return 2;
    const auto at = m.find("sensitivity: ");
    int done = 0, total = 0;
    if (at != std::string::npos && std::sscanf(m.c_str() + at, "sensitivity: %d of %d", &done, &total) == 2 && total > 0)
      return 5.0 + 90.0 * done / total;
    return -1;
  };
  run_with_progress(
      cb, stages,
      [&](const std::function<void(const std::string&)>& report) {
        request.progress = report;
        s = sensitivity_document(request, tolerance, out_dir);
      },
      [this](const std::string& m) { Log("  %s", m.c_str()); });

  Log("Thermal: sensitivity analysis (tolerance %.3g K, sweeps stop above %.3g K): %s",
      tolerance, 2 * tolerance, out_dir.c_str());
  for (size_t n = 0; n < s.nodes.size(); ++n) {
    // The largest ratio whose difference stays within the tolerance: what the curve allows.
    int within = -1;
    for (size_t k = 0; k < s.ratios[n].size(); ++k)
      if (s.max_abs_dT_K[n][k] <= tolerance) within = int(k);
    if (within < 0)
      Log("  %s (%d faces): %d ratio(s) tried, none within tolerance", s.nodes[n].c_str(),
          s.faces_before[n], int(s.ratios[n].size()));
    else
      Log("  %s (%d faces): %d ratio(s) tried, up to %.2f within tolerance (%d faces, max |dT| "
          "%.3g K)", s.nodes[n].c_str(), s.faces_before[n], int(s.ratios[n].size()),
          s.ratios[n][within], s.faces_after[n][within], s.max_abs_dT_K[n][within]);
  }
  for (const auto& f : s.files) Log("  wrote %s", f.c_str());
  for (const auto& w : s.warnings) Log(GLLogStream::WARNING, ("  " + w).c_str());
  progress(cb, 100, "Thermal: sensitivity analysed");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no reduction driver");
#endif
}

bool ThermodecFilterPlugin::reduce(MeshDocument& md, const RichParameterList& params,
                                   vcg::CallBackPos* cb) {
#ifdef THERMODEC_FILTER_REDUCE
  const double tolerance = params.getFloat("tolerance_K");
  const bool informed = params.getEnum("strategy") == 0;
  const bool plots = params.getBool("plots");
  const std::string out_dir = output_dir(md, params, "reduction");
  if (params.getInt("rays_per_face") < 0)
    throw thermodec::InvalidInput("rays_per_face must be >= 0 (0 = the model's)");
  progress(cb, 0, "Thermal: gathering nodes");
  const DocumentMesh dm = mesh_with_nodes(md);
  ModelFileChoice model;
  DocumentModelRequest request = reduction_request(md, dm, params, model);
  Log(model.path.isEmpty() ? GLLogStream::WARNING : GLLogStream::FILTER,
      "%s", ("Thermal: physics-informed decimation: " + model_line(model)).c_str());
  std::vector<std::string> case_files;
  for (const QString& f : text_parameter(params, "case_files").split(';', Qt::SkipEmptyParts))
    if (!f.trimmed().isEmpty()) case_files.push_back(f.trimmed().toStdString());
  DocumentReduction r;
  // reduce's stages (reduction/reduce_model.cpp); the sweep reports its nodes as "k/n".
  const StageOf ordered = ordered_stages({{"sampling: estimating", 2}, {"reference:", 6}, {"noise floor:", 10},
                                          {"noise floor ", 22}, {"decimation:", 25}, {"sensitivity analysis", 27},
                                          {"uniform reduction", 30}, {"prediction and reduction", 60},
                                          {"verification:", 85}, {"verification: max", 98}});
  const StageOf stages = [ordered](const std::string& m) -> double {
    const auto at = m.find("sensitivity: ");
    int done = 0, total = 0;
    if (at != std::string::npos && std::sscanf(m.c_str() + at, "sensitivity: %d/%d", &done, &total) == 2 && total > 0)
      return 27.0 + 33.0 * done / total;
    return ordered(m);
  };
  run_with_progress(
      cb, stages,
      [&](const std::function<void(const std::string&)>& report) {
        request.progress = report;
        r = reduce_document(request, tolerance, informed, out_dir, plots, case_files, params.getBool("merge_nodes"));
      },
      [this](const std::string& m) { Log("  %s", m.c_str()); });
  const auto layers = add_layers(md, dm, r.mesh, "reduced");
  if (!r.merged.empty()) name_merged_nodes(dm, layers, r);

  Log("Thermal: physics-informed decimation (%s, tolerance %.3g K): %d -> %d faces, verified "
      "max |dT| %.3g K, noise floor %.3g K, %d new layer(s), results in %s",
      informed ? "informed" : "uniform", tolerance, dm.mesh.num_faces(), r.mesh.num_faces(),
      r.max_temperature_difference_K, r.noise_floor_K, int(layers.size()), out_dir.c_str());
  for (const QString& line : QString::fromStdString(r.summary).split('\n', Qt::SkipEmptyParts))
    Log("  %s", qUtf8Printable(line));
  for (const auto& w : r.warnings) Log(GLLogStream::WARNING, ("  plot not written: " + w).c_str());
  if (!r.merged.empty()) {  // last, where the log pane shows it
    std::string list;
    for (const auto& m : r.merged) list += (list.empty() ? "" : "; ") + m.name + " = " + member_list(m.members);
    Log("Thermal: %d merged node(s), isothermal, coloured and named as one (the reduced layer's model is now %s): %s",
        int(r.merged.size()), r.model_file.c_str(), list.c_str());
  }
  progress(cb, 100, "Thermal: reduced");
  return true;
#else
  throw thermodec::InvalidInput("this build of thermodec has no reduction driver");
#endif
}

MESHLAB_PLUGIN_NAME_EXPORTER(ThermodecFilterPlugin)
