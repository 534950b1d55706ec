// Writing a model: the mesh (.obj or .ply, nodes and materials per face) and the model file
// beside it, so that load_model reads back the same model.
#include <filesystem>

#include "model_json.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/nodes/model_sections.h"

namespace thermodec {
namespace fs = std::filesystem;
using namespace model_json;
void save_model(const ThermalModel& model, const fs::path& json_path, const fs::path& mesh_path) {
  const std::string ext = lower_extension(mesh_path);
  if (ext != ".obj" && ext != ".ply")
    throw InvalidInput(mesh_path.string() + ": a model's mesh must be .obj or .ply (STL cannot hold node groups)");
  if (lower_extension(json_path) != ".json") throw InvalidInput(json_path.string() + ": the model file must end in .json");
  const Mesh& mesh = model.mesh;
  const int nf = mesh.num_faces();
  if (mesh.face_node.size() != nf || mesh.face_material.size() != nf)
    throw InvalidInput("save_model: the model's mesh has no node or material per face");
  if (mesh.node_names.size() != model.nodes.size() || mesh.material_names.size() != model.materials.size())
    throw InvalidInput("save_model: the mesh's node/material names do not match the model's nodes/materials");
  for (int f = 0; f < nf; ++f)
    if (mesh.face_node[f] < 0 || mesh.face_node[f] >= static_cast<int>(model.nodes.size()))
      throw InvalidInput("save_model: face " + std::to_string(f) + " has no valid node");
  if (model.default_material < 0 || model.default_material >= static_cast<int>(model.materials.size()))
    throw InvalidInput("save_model: default_material out of range");

  json j;
  std::error_code ec;
  const fs::path json_dir = fs::absolute(json_path, ec).parent_path();
  fs::path rel = fs::absolute(mesh_path, ec).lexically_relative(json_dir);
  if (rel.empty()) rel = fs::absolute(mesh_path, ec);
  j["mesh"] = rel.generic_string();
  j["unit_scale"] = 1.0;  // the mesh is written in metres
  json mats = json::object();
  for (const auto& m : model.materials) mats[m.name] = {{"absorptivity", m.absorptivity}, {"emissivity", m.emissivity}};
  j["materials"] = mats;
  j["default_material"] = model.materials[model.default_material].name;
  json nodes = json::object();
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const Node& node = model.nodes[n];
    json v = json::object();
    if (node.material >= 0) v["material"] = model.materials.at(node.material).name;
    v["capacitance"] = node.capacitance_J_per_K;
    if (node.power_schedule_W.empty()) v["power"] = node.power_W;
    else {
      json s = json::array();
      for (const auto& [t, w] : node.power_schedule_W) s.push_back({t, w});
      v["power_schedule_W"] = s;
    }
    if (node.heater) v["heater"] = {{"on_K", node.heater->on_K}, {"off_K", node.heater->off_K}, {"power_W", node.heater->power_W}};
    if (node.fixed_temperature_K) v["fixed_temperature"] = *node.fixed_temperature_K;
    if (node.sampling_boost != Node::SamplingBoost{})
      v["sampling_boost"] = {{"ir", node.sampling_boost.ir}, {"loads", node.sampling_boost.loads}};
    // Sidedness is stated here when it is uniform over the node; otherwise only the mesh
    // file (PLY property, OBJ comment) carries it per face.
    int back = -2;
    bool uniform = true;
    for (int f = 0; f < nf && uniform; ++f) {
      if (mesh.face_node[f] != static_cast<int>(n)) continue;
      const int b = mesh.face_back_material.size() == nf ? mesh.face_back_material[f] : -1;
      if (back == -2) back = b;
      uniform = b == back;
    }
    if (uniform && back == -1) v["two_sided"] = false;
    if (uniform && back >= 0) {
      v["two_sided"] = true;
      v["back_material"] = model.materials.at(back).name;
    }
    nodes[node.name] = v;
  }
  j["nodes"] = nodes;
  json links = json::array();
  for (const auto& c : model.conductances)
    links.push_back({{"from", model.nodes.at(c.from).name}, {"to", model.nodes.at(c.to).name}, {"value", c.conductance_W_per_K}});
  j["conductances"] = links;
  j["environment"] = environment_json(model.environment);
  j["analysis"] = analysis_json(model.analysis);
  j["radiation"] = {{"rays_per_face", model.radiation.rays_per_face},
                    {"min_rays_per_node", model.radiation.min_rays_per_node},
                    {"seed", model.radiation.seed}};
  if (model.certificate) j["certificate"] = certificate_json(*model.certificate);
  if (!model.node_map.empty()) {
    json m = json::object();
    for (const auto& [original, merged] : model.node_map) m[original] = merged;
    j["node_map"] = m;
  }

  MeshWriteOptions mesh_options;
  mesh_options.protected_inputs = {json_path};
  write_mesh(mesh_path, mesh, mesh_options);
  write_text_atomically(json_path, j.dump(2) + "\n", {mesh_path});
}

}  // namespace thermodec
