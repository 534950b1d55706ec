#include "document_mesh.h"

#include <QFile>
#include <QFileInfo>
#include <QTextStream>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "thermodec/common/errors.h"

namespace thermodec_meshlab {
namespace {

using Alloc = vcg::tri::Allocator<CMeshO>;
const char* const kResult = "thermodec_result";          // what a thermodec filter made
const char* const kNames = "thermodec_node_names";       // node id -> name
const char* const kFile = "thermodec_source_file";       // the file a result's nodes came from
const char* const kModelFile = "thermodec_model_file";   // the model file last used
const char* const kFaceNode = "thermodec_node";          // per face: the document node id
const char* const kNodeLayer = "thermodec_node_layer";   // a layer read as one node

template <class T>
bool mesh_attribute(CMeshO& cm, const char* name, T& out) {
  auto h = Alloc::FindPerMeshAttribute<T>(cm, name);
  if (!Alloc::IsValidHandle(cm, h)) return false;
  out = h();
  return true;
}
template <class T>
void set_mesh_attribute(CMeshO& cm, const char* name, const T& value) {
  auto h = Alloc::GetPerMeshAttribute<T>(cm, name);
  h() = value;
}

std::string label(const MeshModel& layer) { return layer.label().toStdString(); }

// A layer's node name: its label without a mesh-file extension, so that the layers of a
// one-file-per-node project ("body_px.ply") match the model file's node names ("body_px").
std::string node_name(const MeshModel& layer) { return layer_stem(layer).toStdString(); }

// `comment thermodec node <id> <name>` lines of a PLY header (thermodec's PLY writer).
std::map<int, std::string> ply_node_names(const QString& path) {
  std::map<int, std::string> names;
  if (!path.endsWith(".ply", Qt::CaseInsensitive)) return names;
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) return names;
  for (int n = 0; n < 100000 && !file.atEnd(); ++n) {
    const QString line = QString::fromUtf8(file.readLine()).trimmed();
    if (line == "end_header") break;
    const QStringList w = line.split(' ', Qt::SkipEmptyParts);
    if (w.size() >= 5 && (w[0] == "comment" || w[0] == "obj_info") && w[1] == "thermodec" && w[2] == "node") {
      bool ok = false;
      const int id = w[3].toInt(&ok);
      if (ok && id >= 0) names[id] = QStringList(w.mid(4)).join(' ').toStdString();
    }
  }
  return names;
}

// Appends the live part of `layer` to `dm`; returns the number of faces appended.
int append_layer(DocumentMesh& dm, MeshModel& layer, int node) {
  CMeshO& cm = layer.cm;
  std::vector<int> vertex_index(cm.vert.size(), -1);
  int live_faces = 0;
  for (const auto& f : cm.face)
    if (!f.IsD()) ++live_faces;
  if (live_faces == 0)
    throw thermodec::InvalidInput("layer '" + label(layer) + "' has no faces");

  thermodec::Mesh& m = dm.mesh;
  const int v0 = m.num_vertices();
  const int f0 = m.num_faces();
  int nv = v0;
  for (size_t i = 0; i < cm.vert.size(); ++i)
    if (!cm.vert[i].IsD()) vertex_index[i] = nv++;
  m.V.conservativeResize(nv, 3);
  m.F.conservativeResize(f0 + live_faces, 3);
  m.face_node.conservativeResize(f0 + live_faces);
  m.face_material.conservativeResize(f0 + live_faces);
  m.face_back_material.conservativeResize(f0 + live_faces);
  for (size_t i = 0; i < cm.vert.size(); ++i) {
    if (vertex_index[i] < 0) continue;
    // Per-layer transformation matrices are ignored on purpose, as MeshLab's own exporters
    // do unless asked: the document's coordinates are the layer's vertex coordinates.
    const auto& p = cm.vert[i].cP();
    m.V.row(vertex_index[i]) << double(p[0]), double(p[1]), double(p[2]);
  }
  int row = f0;
  for (size_t fi = 0; fi < cm.face.size(); ++fi) {
    const auto& f = cm.face[fi];
    if (f.IsD()) continue;
    for (int k = 0; k < 3; ++k)
      m.F(row, k) = vertex_index[vcg::tri::Index(cm, f.cV(k))];
    m.face_node[row] = node;
    m.face_material[row] = -1;
    m.face_back_material[row] = -1;
    dm.origin.push_back({&layer, static_cast<int>(fi)});
    ++row;
  }
  return live_faces;
}

}  // namespace

DocumentMesh mesh_from_layer(MeshModel& layer) {
  DocumentMesh dm;
  dm.mesh.V.resize(0, 3);
  dm.mesh.F.resize(0, 3);
  append_layer(dm, layer, -1);
  return dm;
}

namespace {

// Every layer not made by thermodec, each one node.
DocumentMesh nodes_from_layers(MeshDocument& md, const std::vector<MeshModel*>& layers) {
  DocumentMesh dm;
  dm.mesh.V.resize(0, 3);
  dm.mesh.F.resize(0, 3);
  dm.source = NodeSource::Layers;
  for (MeshModel* layer : layers) {
    const int node = static_cast<int>(dm.node_ids.size());
    append_layer(dm, *layer, node);
    dm.node_ids.push_back(layer->id());
    dm.mesh.node_names.push_back(node_name(*layer));
    // Its face quality may hold temperatures later: it stays a node layer.
    set_mesh_attribute(layer->cm, kNodeLayer, std::string("node"));
  }
  return dm;
}

}  // namespace

DocumentMesh mesh_with_nodes(MeshDocument& md) {
  if (md.meshList.empty() || md.mm() == nullptr)
    throw thermodec::InvalidInput("the document has no mesh layer");
  MeshModel& layer = *md.mm();
  auto own_ids = Alloc::FindPerFaceAttribute<int>(layer.cm, kFaceNode);
  const bool has_own_ids = Alloc::IsValidHandle(layer.cm, own_ids);
  std::string node_layer;
  const bool read_as_node = mesh_attribute(layer.cm, kNodeLayer, node_layer);
  if (!has_own_ids && (read_as_node || !layer.hasDataMask(MeshModel::MM_FACEQUALITY))) {
    std::vector<MeshModel*> inputs;
    for (MeshModel* m : md.meshList)
      if (!is_result_layer(*m)) inputs.push_back(m);
    if (inputs.size() > 1 && !is_result_layer(layer)) return nodes_from_layers(md, inputs);
    throw thermodec::InvalidInput("no nodes: layer '" + label(layer) +
                                  "' has no face quality holding node ids (run 'Thermal: "
                                  "assign nodes' first, or open one layer per node)");
  }
  DocumentMesh dm;
  dm.mesh.V.resize(0, 3);
  dm.mesh.F.resize(0, 3);
  dm.source = NodeSource::FaceQuality;
  dm.layer = &layer;
  append_layer(dm, layer, -1);
  // Node ids are whatever integers the layer holds; they are compacted to 0..n-1 in ascending
  // id order so that node order, and thus every result, is independent of face order.
  std::map<int, int> node_of_id;
  std::vector<int> id_of_face(dm.origin.size());
  for (size_t f = 0; f < dm.origin.size(); ++f) {
    const int face = dm.origin[f].face;
    if (has_own_ids) {
      id_of_face[f] = own_ids[face];
    } else {
      const double q = layer.cm.face[face].cQ();
      if (!std::isfinite(q) || q < 0 || q != std::floor(q) || q > 1e9)
        throw thermodec::InvalidInput("layer '" + label(layer) + "': face " + std::to_string(face) +
                                      " has quality " + std::to_string(q) + ", not a node id (integer >= 0)");
      id_of_face[f] = static_cast<int>(q);
    }
    node_of_id.emplace(id_of_face[f], 0);
  }
  const std::map<int, std::string> names = node_names_of(layer);
  for (auto& entry : node_of_id) {
    entry.second = static_cast<int>(dm.node_ids.size());
    dm.node_ids.push_back(entry.first);
    const auto named = names.find(entry.first);
    char name[32];
    std::snprintf(name, sizeof name, "node_%03d", entry.first);
    dm.mesh.node_names.push_back(named != names.end() && !named->second.empty() ? named->second : name);
  }
  for (size_t f = 0; f < dm.origin.size(); ++f) dm.mesh.face_node[f] = node_of_id[id_of_face[f]];
  return dm;
}

DocumentMesh mesh_with_optional_nodes(MeshDocument& md) {
  int inputs = 0;
  for (MeshModel* m : md.meshList) inputs += !is_result_layer(*m);
  if (md.mm() != nullptr &&
      (inputs > 1 || md.mm()->hasDataMask(MeshModel::MM_FACEQUALITY) ||
       Alloc::IsValidHandle(md.mm()->cm, Alloc::FindPerFaceAttribute<int>(md.mm()->cm, kFaceNode))))
    return mesh_with_nodes(md);
  if (md.mm() == nullptr) throw thermodec::InvalidInput("the document has no mesh layer");
  return mesh_from_layer(*md.mm());
}

namespace {

// Copies the faces of `mesh` listed in `faces` (and the vertices they use) into `cm`.
void fill_layer(CMeshO& cm, const thermodec::Mesh& mesh, const std::vector<int>& faces) {
  std::vector<int> vertex_of(mesh.num_vertices(), -1);
  int nv = 0;
  for (int f : faces)
    for (int k = 0; k < 3; ++k)
      if (vertex_of[mesh.F(f, k)] < 0) vertex_of[mesh.F(f, k)] = nv++;
  auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(cm, nv);
  (void)vi;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (vertex_of[v] >= 0)
      cm.vert[vertex_of[v]].P() = CMeshO::CoordType(CMeshO::ScalarType(mesh.V(v, 0)),
                                                   CMeshO::ScalarType(mesh.V(v, 1)),
                                                   CMeshO::ScalarType(mesh.V(v, 2)));
  vcg::tri::Allocator<CMeshO>::AddFaces(cm, faces.size());
  for (size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) cm.face[i].V(k) = &cm.vert[vertex_of[mesh.F(faces[i], k)]];
}

}  // namespace

std::vector<MeshModel*> add_layers(MeshDocument& md, const DocumentMesh& dm,
                                   const thermodec::Mesh& mesh, const QString& suffix) {
  if (mesh.num_faces() == 0) throw thermodec::InvalidInput("the result has no faces");
  std::vector<MeshModel*> layers;
  auto finish = [&](MeshModel* layer) {
    layer->UpdateBoxAndNormals();
    layers.push_back(layer);
  };
  const int node_count = static_cast<int>(dm.node_ids.size());
  if (dm.source == NodeSource::Layers) {
    std::vector<std::vector<int>> faces_of_node(node_count);
    for (int f = 0; f < mesh.num_faces(); ++f)
      if (mesh.face_node[f] >= 0 && mesh.face_node[f] < node_count)
        faces_of_node[mesh.face_node[f]].push_back(f);
    for (int n = 0; n < node_count; ++n) {
      if (faces_of_node[n].empty()) continue;
      const QString name = result_label(QString::fromStdString(dm.mesh.node_names[n]) + " " + suffix);
      MeshModel* layer = md.addNewMesh("", name, false);
      fill_layer(layer->cm, mesh, faces_of_node[n]);
      MeshModel* source = md.getMesh(dm.node_ids[n]);
      layer->cm.Tr = source->cm.Tr;
      tag_result_layer(*layer, suffix.toStdString(), *source);
      hide_layer(md, *source);
      layer->updateDataMask(MeshModel::MM_FACECOLOR);
      for (auto& face : layer->cm.face) face.C() = node_color(n, node_count);
      finish(layer);
    }
    if (!layers.empty()) md.setCurrentMesh(layers.front()->id());
    return layers;
  }
  std::vector<int> all(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) all[f] = f;
  MeshModel* source = dm.layer != nullptr ? dm.layer : md.mm();
  MeshModel* layer = md.addNewMesh("", result_label(result_stem(*source) + " " + suffix), false);
  fill_layer(layer->cm, mesh, all);
  layer->cm.Tr = source->cm.Tr;
  tag_result_layer(*layer, suffix.toStdString(), *source);
  hide_layer(md, *source);
  if (dm.source == NodeSource::FaceQuality) {
    layer->updateDataMask(MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int n = mesh.face_node[f];
      layer->cm.face[f].Q() = n >= 0 ? CMeshO::ScalarType(dm.node_ids[n]) : CMeshO::ScalarType(-1);
      layer->cm.face[f].C() = node_color(n, node_count);
    }
  }
  finish(layer);
  md.setCurrentMesh(layer->id());
  return layers;
}

QString layer_stem(const MeshModel& layer) {
  const QFileInfo info(layer.label());
  const QString ext = info.suffix().toLower();
  if (ext == "ply" || ext == "obj" || ext == "stl" || ext == "off") return info.completeBaseName();
  return layer.label();
}

QString result_label(const QString& text) { return text + ".ply"; }

QString result_stem(MeshModel& layer) {
  // A result of a result is named after the first input ("satellite reduced", not "satellite
  // mean temperature 240.50 to 266.03 K reduced").
  if (is_result_layer(layer)) {
    const QFileInfo file(layer_file(layer));
    if (!file.completeBaseName().isEmpty()) return file.completeBaseName();
  }
  return layer_stem(layer);
}

void tag_result_layer(MeshModel& layer, const std::string& what, MeshModel& source) {
  set_mesh_attribute(layer.cm, kResult, what);
  set_node_names(layer, node_names_of(source));
  set_mesh_attribute(layer.cm, kFile, layer_file(source).toStdString());
  set_mesh_attribute(layer.cm, kModelFile, layer_model_file(source).toStdString());
}

bool is_result_layer(MeshModel& layer) {
  std::string what;
  return mesh_attribute(layer.cm, kResult, what);
}

void set_layer_node_ids(MeshModel& layer, const std::vector<int>& ids) {
  auto h = Alloc::GetPerFaceAttribute<int>(layer.cm, kFaceNode);
  size_t k = 0;
  for (size_t f = 0; f < layer.cm.face.size(); ++f)
    if (!layer.cm.face[f].IsD()) h[f] = k < ids.size() ? ids[k++] : -1;
}

std::map<int, std::string> node_names_of(MeshModel& layer) {
  std::map<int, std::string> names;
  if (mesh_attribute(layer.cm, kNames, names)) return names;
  return ply_node_names(layer.fullName());
}

void set_node_names(MeshModel& layer, const std::map<int, std::string>& names) {
  set_mesh_attribute(layer.cm, kNames, names);
}

QString layer_file(MeshModel& layer) {
  std::string file;
  if (mesh_attribute(layer.cm, kFile, file)) return QString::fromStdString(file);
  return layer.fullName();
}

QString layer_model_file(MeshModel& layer) {
  std::string file;
  return mesh_attribute(layer.cm, kModelFile, file) ? QString::fromStdString(file) : QString();
}

void set_layer_model_file(MeshModel& layer, const QString& path) {
  set_mesh_attribute(layer.cm, kModelFile, path.toStdString());
}

void hide_layer(MeshDocument& md, MeshModel& layer) { md.setVisible(layer.id(), false); }

vcg::Color4b node_color(int node, int node_count) {
  if (node < 0) return vcg::Color4b::Gray;
  return vcg::Color4b::Scatter(std::max(node_count, 1), node, 0.6f, 0.9f);
}

void set_face_quality(const DocumentMesh& dm, const std::vector<double>& value) {
  assert(value.size() == dm.origin.size());
  for (size_t f = 0; f < dm.origin.size(); ++f) {
    MeshModel& layer = *dm.origin[f].layer;
    if (!layer.hasDataMask(MeshModel::MM_FACEQUALITY)) layer.updateDataMask(MeshModel::MM_FACEQUALITY);
    layer.cm.face[dm.origin[f].face].Q() = static_cast<CMeshO::ScalarType>(value[f]);
  }
}

void paint_nodes(const DocumentMesh& dm) {
  const int n = static_cast<int>(dm.mesh.node_names.size());
  for (size_t f = 0; f < dm.origin.size(); ++f) {
    MeshModel& layer = *dm.origin[f].layer;
    if (!layer.hasDataMask(MeshModel::MM_FACECOLOR)) layer.updateDataMask(MeshModel::MM_FACECOLOR);
    layer.cm.face[dm.origin[f].face].C() = node_color(dm.mesh.face_node[f], n);
  }
}

}  // namespace thermodec_meshlab
