#include "filter_thermodec.h"

#include <exception>

#include "document_mesh.h"
#include "thermodec/common/errors.h"
#ifdef THERMODEC_FILTER_ASSIGN_NODES
#include "thermodec/nodes/automatic_nodes.h"
#endif

using namespace thermodec_meshlab;

namespace {

// MeshLab's progress callback may be null (scripted calls); never dereference it blindly.
inline void progress(vcg::CallBackPos* cb, int percent, const char* what) {
  if (cb != nullptr) cb(percent, what);
}

}  // namespace

ThermodecFilterPlugin::ThermodecFilterPlugin() {
#ifdef THERMODEC_FILTER_ASSIGN_NODES
  typeList << FP_ASSIGN_NODES;
#endif
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString ThermodecFilterPlugin::pluginName() const { return "FilterThermodec"; }

QString ThermodecFilterPlugin::filterName(FilterIDType filter) const {
  switch (filter) {
    case FP_ASSIGN_NODES: return "Thermal: assign nodes";
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
  }
  assert(false);
  return QString();
}

MeshFilterInterface::FilterClass ThermodecFilterPlugin::getClass(QAction* action) {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return FilterClass(Quality | FaceColoring);
  }
  assert(false);
  return Quality;
}

MeshFilterInterface::FILTER_ARITY ThermodecFilterPlugin::filterArity(QAction* action) const {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return SINGLE_MESH;
  }
  assert(false);
  return SINGLE_MESH;
}

int ThermodecFilterPlugin::getRequirements(QAction* action) {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR;
  }
  assert(false);
  return MeshModel::MM_NONE;
}

int ThermodecFilterPlugin::getPreConditions(QAction* action) const {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return MeshModel::MM_FACENUMBER;
  }
  assert(false);
  return MeshModel::MM_NONE;
}

int ThermodecFilterPlugin::postCondition(QAction* action) const {
  switch (ID(action)) {
    case FP_ASSIGN_NODES: return MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR;
  }
  assert(false);
  return MeshModel::MM_NONE;
}

void ThermodecFilterPlugin::initParameterSet(QAction* action, MeshModel& /*m*/,
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
  }
}

bool ThermodecFilterPlugin::applyFilter(QAction* action, MeshDocument& md,
                                        const RichParameterList& params, vcg::CallBackPos* cb) {
  // Every user-caused failure in the core is a thermodec::Error with a one-line message; it
  // goes to MeshLab's error mechanism and log. Nothing may escape into the host.
  try {
    switch (ID(action)) {
      case FP_ASSIGN_NODES: return assign_nodes(md, params, cb);
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

MESHLAB_PLUGIN_NAME_EXPORTER(ThermodecFilterPlugin)
