#include "core_calls.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace fs = std::filesystem;

namespace thermodec_meshlab {
namespace {

int index_of_node(const thermodec::ThermalModel& model, const std::string& name) {
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (model.nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

// The bare-mesh defaults live in load_model (they are the documented defaults of
// `thermodec simulate mesh.ply`); going through a temporary PLY keeps them in one place.
thermodec::ThermalModel default_model(const thermodec::Mesh& mesh) {
  const fs::path dir = fs::temp_directory_path() /
                       ("thermodec-meshlab-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path ply = dir / "document.ply";
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  thermodec::write_mesh(ply, mesh);
  return thermodec::load_model(ply);
}

// Most common value of `value` over the faces of each model node (-1 if it has none).
std::vector<int> majority_per_node(const thermodec::Mesh& mesh, const Eigen::VectorXi& value,
                                   int node_count) {
  std::vector<std::map<int, int>> count(node_count);
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.face_node[f] >= 0 && mesh.face_node[f] < node_count) ++count[mesh.face_node[f]][value[f]];
  std::vector<int> best(node_count, -1);
  for (int n = 0; n < node_count; ++n) {
    int most = 0;
    for (const auto& [v, c] : count[n])  // ascending value: ties go to the smaller index
      if (c > most) most = c, best[n] = v;
  }
  return best;
}

}  // namespace

NodeTemperatures simulate_document(const thermodec::Mesh& mesh, const std::vector<int>& node_ids,
                                   bool ids_index_model_nodes, const std::string& model_file,
                                   int rays_per_face,
                                   const std::function<void(const std::string&)>& progress) {
  const int doc_nodes = static_cast<int>(mesh.node_names.size());
  if (doc_nodes == 0 || mesh.num_faces() == 0)
    throw thermodec::InvalidInput("no nodes: the document mesh has no faces with a node");
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.face_node[f] < 0 || mesh.face_node[f] >= doc_nodes)
      throw thermodec::InvalidInput("face " + std::to_string(f) + " has no node");

  NodeTemperatures out;
  out.nodes = mesh.node_names;
  thermodec::ThermalModel model;
  std::vector<int> model_node(doc_nodes, -1);
  if (model_file.empty()) {
    model = default_model(mesh);
    for (int i = 0; i < doc_nodes; ++i) {
      model_node[i] = index_of_node(model, mesh.node_names[i]);
      if (model_node[i] < 0) model_node[i] = i;  // same order when names were not kept
    }
    out.model_description = "core defaults (no model file)";
  } else {
    model = thermodec::load_model(model_file);
    const int n_model = static_cast<int>(model.nodes.size());
    for (int i = 0; i < doc_nodes; ++i) {
      model_node[i] = index_of_node(model, mesh.node_names[i]);
      if (model_node[i] < 0 && ids_index_model_nodes && node_ids[i] < n_model) model_node[i] = node_ids[i];
      if (model_node[i] < 0)
        throw thermodec::InvalidInput(model_file + ": the model has no node '" + mesh.node_names[i] +
                                      "' (" + std::to_string(n_model) + " nodes)");
    }
    const std::vector<int> front = majority_per_node(model.mesh, model.mesh.face_material, n_model);
    const std::vector<int> back = majority_per_node(model.mesh, model.mesh.face_back_material, n_model);
    thermodec::Mesh m = mesh;
    m.node_names.clear();
    for (const auto& n : model.nodes) m.node_names.push_back(n.name);
    m.material_names = model.mesh.material_names;
    for (int f = 0; f < m.num_faces(); ++f) {
      const int n = model_node[mesh.face_node[f]];
      m.face_node[f] = n;
      m.face_material[f] = front[n] >= 0 ? front[n]
                           : model.nodes[n].material >= 0 ? model.nodes[n].material
                                                          : model.default_material;
      m.face_back_material[f] = back[n];
    }
    model.mesh = std::move(m);
    out.model_description = model_file;
  }
  if (rays_per_face > 0) model.radiation.rays_per_face = rays_per_face;
  out.model_nodes.resize(doc_nodes);
  for (int i = 0; i < doc_nodes; ++i) out.model_nodes[i] = model.nodes[model_node[i]].name;

  thermodec::ModelSimulationSettings settings;
  settings.progress = progress;
  const thermodec::SimulationResult r = thermodec::simulate_model(model, settings);
  out.transient = r.transient;
  out.times = static_cast<int>(r.times_s.size());
  out.orbits = r.orbits;
  out.periodicity_residual_K = r.periodicity_residual_K;
  for (int i = 0; i < doc_nodes; ++i) {
    const auto row = r.temperature_K.row(model_node[i]);
    out.min_K.push_back(row.minCoeff());
    out.mean_K.push_back(row.mean());
    out.max_K.push_back(row.maxCoeff());
  }
  return out;
}

}  // namespace thermodec_meshlab
