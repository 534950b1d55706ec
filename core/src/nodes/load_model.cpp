// The thermal model file (docs/model-format.md). Validation is strict everywhere: an unknown
// key is most often a typo that would otherwise silently fall back to a default (a misspelt
// "enviroment" would run the default orbit), so it is an error with the nearest known key
// suggested; ModelLoadOptions::allow_unknown_keys downgrades it to a warning. Keys starting
// with '_' and "description" are free for comments.
#include "thermodec/nodes/load_model.h"

#include <algorithm>
#include <map>
#include <set>

#include "model_json.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/format_bdf.h"
#include "thermodec/mesh/geometry_range.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"

namespace thermodec {
namespace {
namespace fs = std::filesystem;
using namespace model_json;

bool is_mesh_path(const fs::path& p) {
  const std::string ext = lower_extension(p);
  return ext == ".obj" || ext == ".ply" || ext == ".stl" || is_nastran_path(p);
}

constexpr const char* kDefaultMaterialName = "default";
// Documented in docs/model-format.md ("Defaults"): a generic grey coating, neither a white
// paint nor a black one, so an unconfigured model is not mistaken for a designed one.
constexpr double kDefaultAbsorptivity = 0.5;
constexpr double kDefaultEmissivity = 0.8;
constexpr const char* kUngroupedNodeName = "ungrouped";

int index_of(const std::vector<Material>& v, const std::string& name) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i].name == name) return static_cast<int>(i);
  return -1;
}
int index_of(const std::vector<Node>& v, const std::string& name) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i].name == name) return static_cast<int>(i);
  return -1;
}

// Makes every face belong to a node: a mesh without any group gets the automatic nodal
// breakdown; stray faces of a grouped mesh go to the node "ungrouped".
void ensure_nodes(Mesh& mesh, const AutomaticNodeOptions& automatic) {
  const bool any_group = mesh.face_node.size() > 0 && mesh.face_node.maxCoeff() >= 0;
  if (!any_group) {
    assign_automatic_nodes(mesh, automatic);
    return;
  }
  if (mesh.face_node.minCoeff() >= 0) return;
  auto it = std::find(mesh.node_names.begin(), mesh.node_names.end(), kUngroupedNodeName);
  const int id = static_cast<int>(it - mesh.node_names.begin());
  if (it == mesh.node_names.end()) mesh.node_names.push_back(kUngroupedNodeName);
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.face_node[f] < 0) mesh.face_node[f] = id;
}

struct NodeSides {
  std::optional<bool> two_sided;
  int back_material = -1;
};

// Resolves every face's front and back material to model material indices (see the model
// format's precedence rules) and makes the mesh's name tables those of the model.
void resolve_faces(ThermalModel& model, const std::vector<NodeSides>& sides, const std::string& mesh_file) {
  Mesh& mesh = model.mesh;
  auto model_material_of = [&](int file_material) -> int {
    if (file_material < 0) return -1;
    const std::string& name = mesh.material_names[file_material];
    const int m = index_of(model.materials, name);
    if (m < 0) throw InvalidInput(mesh_file + ": material '" + name + "' used by the mesh is not defined in the model's 'materials'");
    return m;
  };
  // Only materials actually used by a face must exist in the model.
  std::vector<char> used(mesh.material_names.size(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int m : {mesh.face_material[f], mesh.face_back_material[f]})
      if (m >= 0) used[m] = 1;
  std::vector<int> map_material(mesh.material_names.size(), -1);
  for (std::size_t i = 0; i < mesh.material_names.size(); ++i)
    if (used[i]) map_material[i] = model_material_of(static_cast<int>(i));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Node& node = model.nodes[mesh.face_node[f]];
    const int file_front = mesh.face_material[f];
    const int front = file_front >= 0 ? map_material[file_front]
                      : node.material >= 0 ? node.material
                                           : model.default_material;
    mesh.face_material[f] = front;
    const NodeSides& s = sides[mesh.face_node[f]];
    const int file_back = mesh.face_back_material[f];
    if (s.two_sided.has_value())
      mesh.face_back_material[f] = *s.two_sided ? (s.back_material >= 0 ? s.back_material : front) : -1;
    else
      mesh.face_back_material[f] = file_back >= 0 ? map_material[file_back] : -1;
  }
  mesh.material_names.clear();
  for (const auto& m : model.materials) mesh.material_names.push_back(m.name);
  mesh.node_names.clear();
  for (const auto& n : model.nodes) mesh.node_names.push_back(n.name);
}

ThermalModel model_from_bare_mesh(const fs::path& path, const ModelLoadOptions& options) {
  ThermalModel model;
  model.mesh_path = path;
  model.mesh = read_mesh(path, options.mesh);
  Eigen::VectorXi two_sided;
  // Only a mesh without any group is a raw CAD export; a grouped mesh was prepared for
  // thermodec (or by it) and is taken as written.
  const bool grouped = model.mesh.face_node.size() > 0 && model.mesh.face_node.maxCoeff() >= 0;
  if (options.clean_bare_mesh && !grouped) {
    BareMeshCleanupResult cleaned = cleanup_bare_mesh(model.mesh, options.cleanup);
    model.mesh = std::move(cleaned.mesh);
    two_sided = std::move(cleaned.two_sided);
    model.mesh_cleanup = cleaned.report;
  }
  ensure_nodes(model.mesh, options.automatic_nodes);
  model.materials.push_back({kDefaultMaterialName, kDefaultAbsorptivity, kDefaultEmissivity});
  model.default_material = 0;
  // With no model file there are no coating properties: materials named in the mesh get the
  // default coating, so the model is valid and the names are kept for a later model file.
  for (const auto& name : model.mesh.material_names)
    if (index_of(model.materials, name) < 0) model.materials.push_back({name, kDefaultAbsorptivity, kDefaultEmissivity});
  // NASTRAN decks carry coatings as RADM cards (alpha, eps of the PSHELL's material).
  if (is_nastran_path(path))
    for (const BdfRadiationProperties& r : read_bdf_radiation_properties(path)) {
      const int m = index_of(model.materials, r.material);
      if (m >= 0) model.materials[m].absorptivity = r.absorptivity, model.materials[m].emissivity = r.emissivity;
    }
  for (const auto& name : model.mesh.node_names) {
    Node node;
    node.name = name;
    model.nodes.push_back(node);
  }
  resolve_faces(model, std::vector<NodeSides>(model.nodes.size()), path.string());
  // Faces the cleanup made two-sided whose front material was "the node's": the back radiates
  // with the resolved front.
  for (int f = 0; f < two_sided.size(); ++f)
    if (two_sided[f] && model.mesh.face_back_material[f] < 0) model.mesh.face_back_material[f] = model.mesh.face_material[f];
  return model;
}

// The "materials" section in file order, and the default material (added when no file names it).
void parse_materials(const json& j, const Keys& k, ThermalModel& model) {
  if (j.contains("materials")) {
    const json& mats = j.at("materials");
    k.require_object(mats, "materials");
    for (const auto& item : mats.items()) {
      const std::string key = "materials." + item.key();
      k.require_object(item.value(), key);
      k.only_keys(item.value(), key, {"absorptivity", "emissivity"});
      for (const char* req : {"absorptivity", "emissivity"})
        if (!item.value().contains(req)) k.fail(key, std::string("missing '") + req + "'");
      Material m;
      m.name = item.key();
      k.name(key, m.name);
      m.absorptivity = k.number_in(item.value(), key, "absorptivity", 0, 1, true, "");
      m.emissivity = k.number_in(item.value(), key, "emissivity", 0, 1, true, "");
      model.materials.push_back(m);
    }
  }
  if (j.contains("default_material")) {
    const std::string name = k.string(j, "", "default_material");
    model.default_material = index_of(model.materials, name);
    if (model.default_material < 0) k.fail("default_material", "unknown material '" + name + "' (not in 'materials')");
  } else {
    model.default_material = index_of(model.materials, kDefaultMaterialName);
    if (model.default_material < 0) {
      model.default_material = static_cast<int>(model.materials.size());
      model.materials.push_back({kDefaultMaterialName, kDefaultAbsorptivity, kDefaultEmissivity});
    }
  }
}

// The "conductances" list: GL [W/K] between two nodes of the mesh.
void parse_conductances(const json& j, const Keys& k, ThermalModel& model) {
  if (j.contains("conductances")) {
    const json& list = j.at("conductances");
    if (!list.is_array()) k.fail("conductances", "must be an array of {\"from\", \"to\", \"value\"}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string key = "conductances[" + std::to_string(i) + "]";
      const json& c = list[i];
      k.require_object(c, key);
      k.only_keys(c, key, {"from", "to", "value"});
      for (const char* req : {"from", "to", "value"})
        if (!c.contains(req)) k.fail(key, std::string("missing '") + req + "'");
      Conductance link;
      for (const char* end : {"from", "to"}) {
        const std::string name = k.string(c, key, end);
        const int n = index_of(model.nodes, name);
        if (n < 0) k.fail(key + "." + end, "unknown node '" + name + "' (not a group of the mesh)");
        (std::string(end) == "from" ? link.from : link.to) = n;
      }
      if (link.from == link.to) k.fail(key, "links node '" + model.nodes[link.from].name + "' to itself");
      link.conductance_W_per_K = k.number_in(c, key, "value", 0, 1e12, false, " W/K");
      model.conductances.push_back(link);
    }
  }
}

ThermalModel model_from_json(const fs::path& path, const ModelLoadOptions& options) {
  const std::string file = path.string();
  const Keys k(file, options.allow_unknown_keys);
  const json j = read_json(path);
  k.require_object(j, "");
  if (!j.contains("mesh") && j.contains("environment") && !j.contains("nodes") && !j.contains("materials"))
    k.fail("", "this looks like a load case file (environment/analysis only, no mesh): give it to "
               "`thermodec reduce MODEL --case FILE`; a model file needs a 'mesh' key");
  for (const auto& item : j.items()) {
    static const std::vector<std::string> known = {"mesh", "unit_scale", "materials", "default_material", "nodes",
                                                   "conductances", "environment", "analysis", "radiation", "description",
                                                   "certificate", "node_map"};
    if (std::find(known.begin(), known.end(), item.key()) == known.end() && item.key().rfind("_", 0) != 0)
      k.unknown("", item.key(), known, " at the top level");
  }
  ThermalModel model;
  if (!j.contains("mesh")) k.fail("mesh", "missing: the model needs a mesh file (.obj, .ply or .stl)");
  const fs::path mesh_rel = k.string(j, "", "mesh");
  if (!is_mesh_path(mesh_rel)) k.fail("mesh", "'" + mesh_rel.string() + "' is not a .obj, .ply or .stl file");
  model.mesh_path = mesh_rel.is_absolute() ? mesh_rel : path.parent_path() / mesh_rel;
  // Micrometres to kilometres: far smaller or larger scales put the geometry where the ray
  // tracer's offsets and the double range no longer hold (1e-200 underflows the areas).
  if (j.contains("unit_scale")) model.unit_scale = k.number_in(j, "", "unit_scale", 1e-6, 1e6, false, " m per file unit");

  parse_materials(j, k, model);

  // The mesh: its groups are the nodes.
  model.mesh = read_mesh(model.mesh_path, options.mesh);
  model.mesh.V *= model.unit_scale;
  check_geometry_range(model.mesh.V, model.mesh.F, model.mesh_path.string() + " (scaled by unit_scale)");
  // A raw CAD export (no groups) in a model file that names no nodes and sets no sampling is
  // cleaned as it is when given bare (and so gets the bare-mesh sample budgets): the same mesh
  // reduces the same way either way.
  Eigen::VectorXi two_sided;
  const bool grouped = model.mesh.face_node.size() > 0 && model.mesh.face_node.maxCoeff() >= 0;
  if (options.clean_bare_mesh && !grouped && !j.contains("nodes") && !j.contains("radiation")) {
    BareMeshCleanupResult cleaned = cleanup_bare_mesh(model.mesh, options.cleanup);
    model.mesh = std::move(cleaned.mesh);
    two_sided = std::move(cleaned.two_sided);
    model.mesh_cleanup = cleaned.report;
  }
  ensure_nodes(model.mesh, options.automatic_nodes);
  for (const auto& name : model.mesh.node_names) {
    Node node;
    node.name = name;
    model.nodes.push_back(node);
  }
  std::vector<NodeSides> sides(model.nodes.size());

  if (j.contains("nodes")) {
    const json& nodes = j.at("nodes");
    k.require_object(nodes, "nodes");
    for (const auto& item : nodes.items()) {
      const std::string key = "nodes." + item.key();
      const int n = index_of(model.nodes, item.key());
      if (n < 0) k.fail(key, "no group named '" + item.key() + "' in mesh " + model.mesh_path.string());
      const json& v = item.value();
      k.require_object(v, key);
      k.only_keys(v, key, {"material", "capacitance", "power", "fixed_temperature", "two_sided", "back_material",
                               "sampling_boost", "power_schedule_W", "heater"});
      Node& node = model.nodes[n];
      auto material_key = [&](const char* name) {
        const std::string m = k.string(v, key, name);
        const int id = index_of(model.materials, m);
        if (id < 0) k.fail(key + "." + name, "unknown material '" + m + "' (not in 'materials')");
        return id;
      };
      if (v.contains("material")) node.material = material_key("material");
      if (v.contains("capacitance")) node.capacitance_J_per_K = k.number_in(v, key, "capacitance", 0, 1e15, false, " J/K");
      if (v.contains("power")) node.power_W = k.number(v, key, "power");
      if (v.contains("power_schedule_W")) {
        if (v.contains("power")) k.fail(key, "give either 'power' or 'power_schedule_W', not both");
        node.power_W = 0.0;
        node.power_schedule_W = model_json::power_schedule(v.at("power_schedule_W"), k, key + ".power_schedule_W");
      }
      if (v.contains("heater")) node.heater = model_json::thermostat(v.at("heater"), k, key + ".heater");
      if (v.contains("fixed_temperature")) node.fixed_temperature_K = k.number_in(v, key, "fixed_temperature", 1, 1e5, false, " K");
      if (v.contains("sampling_boost")) {
        const json& b = v.at("sampling_boost");
        const std::string bk = key + ".sampling_boost";
        k.require_object(b, bk);
        k.only_keys(b, bk, {"ir", "loads"});
        const double lo = Node::SamplingBoost::kMin, hi = Node::SamplingBoost::kMax;
        if (b.contains("ir")) node.sampling_boost.ir = k.number_in(b, bk, "ir", lo, hi, false, "");
        if (b.contains("loads")) node.sampling_boost.loads = k.number_in(b, bk, "loads", lo, hi, false, "");
      }
      if (v.contains("two_sided")) sides[n].two_sided = k.boolean(v, key, "two_sided");
      if (v.contains("back_material")) {
        if (sides[n].two_sided == false) k.fail(key + ".back_material", "given for a node with \"two_sided\": false");
        sides[n].two_sided = true;
        sides[n].back_material = material_key("back_material");
      }
    }
  }
  resolve_faces(model, sides, model.mesh_path.string());
  for (int f = 0; f < two_sided.size(); ++f)  // as for a bare mesh (model_from_bare_mesh)
    if (two_sided[f] && model.mesh.face_back_material[f] < 0) model.mesh.face_back_material[f] = model.mesh.face_material[f];

  parse_conductances(j, k, model);
  if (j.contains("environment")) parse_environment(j.at("environment"), k, model.environment);
  if (j.contains("analysis")) parse_analysis(j.at("analysis"), k, model.analysis);
  check_analysis_fits_environment(model.analysis, model.environment, k);
  check_internal_power(model, k);
  if (j.contains("radiation")) parse_radiation(j.at("radiation"), k, model.radiation);
  if (j.contains("certificate")) {
    try {
      model.certificate = certificate_from_json(j.at("certificate"));
    } catch (const InvalidInput& e) {
      k.fail("certificate", e.what());
    }
  }
  if (j.contains("node_map")) {  // original node -> the node of this model it was merged into
    const json& m = j.at("node_map");
    k.require_object(m, "node_map");
    for (const auto& item : m.items()) {
      const std::string merged = k.string(m, "node_map", item.key().c_str());
      if (index_of(model.nodes, merged) < 0) k.fail("node_map." + item.key(), "'" + merged + "' is not a node of the model");
      model.node_map.emplace_back(item.key(), merged);
    }
  }
  return model;
}

}  // namespace

ThermalModel load_model(const fs::path& path, const MeshReadOptions& mesh_options) {
  ModelLoadOptions options;
  options.mesh = mesh_options;
  options.clean_bare_mesh = false;
  return load_model(path, options);
}

ThermalModel load_model(const fs::path& path, const ModelLoadOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError(path.string() + ": no such file");
  if (is_mesh_path(path)) return model_from_bare_mesh(path, options);
  if (lower_extension(path) != ".json")
    throw InvalidInput(path.string() + ": a model is a .json model file or a .obj, .ply or .stl mesh");
  return model_from_json(path, options);
}

ThermalModel load_model(const fs::path& path) { return load_model(path, ModelLoadOptions{}); }

}  // namespace thermodec
