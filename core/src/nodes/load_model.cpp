// The thermal model file (docs/model-format.md). Validation is strict everywhere: an unknown
// key is most often a typo that would otherwise silently fall back to a default (a misspelt
// "enviroment" would run the default orbit), so it is an error with the nearest known key
// suggested; ModelLoadOptions::allow_unknown_keys downgrades it to a warning. Keys starting
// with '_' and "description" are free for comments.
#include "thermodec/nodes/load_model.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/mesh/format_bdf.h"

namespace thermodec {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

std::string lower_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool is_mesh_path(const fs::path& p) {
  const std::string ext = lower_extension(p);
  return ext == ".obj" || ext == ".ply" || ext == ".stl" || is_nastran_path(p);
}

// Error context: the model file and the dotted key path ("nodes.body_px.capacitance").
class Keys {
 public:
  explicit Keys(std::string file, bool allow_unknown = false) : file_(std::move(file)), allow_unknown_(allow_unknown) {}

  //! An unknown key: an error naming the nearest known key, or a warning when allowed.
  void unknown(const std::string& key, const std::string& name, const std::vector<std::string>& known,
               const std::string& context = "") const {
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    const std::string hint = nearest(name, known);
    const std::string what = "unknown key" + context + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                             "; known: " + list;
    if (!allow_unknown_) fail(join(key, name), what + " (--allow-unknown-keys ignores it)");
    std::cerr << "thermodec: warning: " << file_ << ": '" << join(key, name) << "': " << what << "; ignored\n";
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InvalidInput(file_ + ": " + (key.empty() ? std::string() : "'" + key + "': ") + what);
  }

  void require_object(const json& j, const std::string& key) const {
    if (!j.is_object()) fail(key, "must be an object {...}, got " + std::string(j.type_name()));
  }

  void only_keys(const json& obj, const std::string& key, std::initializer_list<const char*> known,
                 const std::string& context = "") const {
    for (const auto& item : obj.items()) {
      if (std::find_if(known.begin(), known.end(), [&](const char* k) { return item.key() == k; }) != known.end()) continue;
      unknown(key, item.key(), std::vector<std::string>(known.begin(), known.end()), context);
    }
  }

  //! The known key closest to `name` by edit distance, if close enough to be a typo.
  static std::string nearest(const std::string& name, const std::vector<std::string>& known) {
    std::string best;
    std::size_t best_d = std::max<std::size_t>(2, name.size() / 3) + 1;
    for (const auto& k : known) {
      std::vector<std::size_t> row(k.size() + 1);
      for (std::size_t j = 0; j <= k.size(); ++j) row[j] = j;
      for (std::size_t i = 1; i <= name.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= k.size(); ++j) {
          const std::size_t up = row[j];
          row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (std::tolower(static_cast<unsigned char>(name[i - 1])) !=
                                                                  std::tolower(static_cast<unsigned char>(k[j - 1])))});
          diag = up;
        }
      }
      if (row[k.size()] < best_d) best_d = row[k.size()], best = k;
    }
    return best;
  }

  double number(const json& obj, const std::string& key, const char* name) const {
    const json& v = obj.at(name);
    if (!v.is_number()) fail(join(key, name), "must be a number, got " + std::string(v.type_name()));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(join(key, name), "must be finite");
    return x;
  }

  double number_in(const json& obj, const std::string& key, const char* name, double lo, double hi,
                   bool lo_open, const char* unit) const {
    const double x = number(obj, key, name);
    if ((lo_open ? !(x > lo) : !(x >= lo)) || !(x <= hi)) {
      std::ostringstream s;
      s << "must be in " << (lo_open ? "(" : "[") << lo << ", " << hi << "]" << unit << ", got " << x;
      fail(join(key, name), s.str());
    }
    return x;
  }

  long long integer(const json& obj, const std::string& key, const char* name, long long lo, long long hi) const {
    const json& v = obj.at(name);
    long long x = 0;
    if (v.is_number_integer()) {
      if (v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi))
        fail(join(key, name), "must be at most " + std::to_string(hi));
      x = v.get<long long>();
    } else if (v.is_number_float() && std::isfinite(v.get<double>()) && v.get<double>() == std::floor(v.get<double>()) &&
               std::abs(v.get<double>()) < 9e15) {
      x = static_cast<long long>(v.get<double>());
    } else {
      fail(join(key, name), "must be an integer, got " + v.dump());
    }
    if (x < lo || x > hi) fail(join(key, name), "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(x));
    return x;
  }

  std::string string(const json& obj, const std::string& key, const char* name) const {
    const json& v = obj.at(name);
    if (!v.is_string() || v.get<std::string>().empty()) fail(join(key, name), "must be a non-empty string");
    return v.get<std::string>();
  }

  bool boolean(const json& obj, const std::string& key, const char* name) const {
    const json& v = obj.at(name);
    if (!v.is_boolean()) fail(join(key, name), "must be true or false");
    return v.get<bool>();
  }

  //! Node and material names end up as whole lines of OBJ and PLY files: one printable line.
  void name(const std::string& key, const std::string& n) const {
    for (const char c : n)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        fail(key, "names must not contain control characters (newline, tab, NUL)");
    if (n.empty() || n.front() == ' ' || n.back() == ' ') fail(key, "names must be non-empty without leading/trailing spaces");
  }

  static std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

 private:
  std::string file_;
  bool allow_unknown_ = false;
};

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
void ensure_nodes(Mesh& mesh) {
  const bool any_group = mesh.face_node.size() > 0 && mesh.face_node.maxCoeff() >= 0;
  if (!any_group) {
    assign_automatic_nodes(mesh);
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

ThermalModel model_from_bare_mesh(const fs::path& path, const MeshReadOptions& options,
                                  const BareMeshCleanupOptions* cleanup) {
  ThermalModel model;
  model.mesh_path = path;
  model.mesh = read_mesh(path, options);
  Eigen::VectorXi two_sided;
  // Only a mesh without any group is a raw CAD export; a grouped mesh was prepared for
  // thermodec (or by it) and is taken as written.
  const bool grouped = model.mesh.face_node.size() > 0 && model.mesh.face_node.maxCoeff() >= 0;
  if (cleanup && !grouped) {
    BareMeshCleanupResult cleaned = cleanup_bare_mesh(model.mesh, *cleanup);
    model.mesh = std::move(cleaned.mesh);
    two_sided = std::move(cleaned.two_sided);
    model.mesh_cleanup = cleaned.report;
  }
  ensure_nodes(model.mesh);
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

// Model and case files are small; a bigger file is a mistake (or /dev/zero), not a model.
constexpr std::uintmax_t kMaxJsonFileBytes = std::uintmax_t{64} << 20;
// No model key nests deeper than 4; the limit keeps recursive code (dump() in messages,
// destruction) far from the stack's end on a file of thousands of '['.
constexpr int kMaxJsonDepth = 32;

json read_json(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw IOError(path.string() + ": not a regular file (a folder, device or FIFO)");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxJsonFileBytes)
    throw IOError(path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                  std::to_string(kMaxJsonFileBytes) + "-byte limit for JSON files");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError(path.string() + ": cannot open for reading");
  std::stringstream s;
  s << in.rdbuf();
  // nlohmann keeps the last of two equal keys; a duplicated node or material would silently
  // lose its first definition, so duplicates are refused while parsing (one key set per open
  // object), as is nesting beyond kMaxJsonDepth.
  std::vector<std::set<std::string>> open_objects;
  const auto check = [&](int depth, json::parse_event_t event, json& parsed) {
    if (depth > kMaxJsonDepth)
      throw InvalidInput(path.string() + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    if (event == json::parse_event_t::object_start) open_objects.emplace_back();
    else if (event == json::parse_event_t::object_end && !open_objects.empty()) open_objects.pop_back();
    else if (event == json::parse_event_t::key && !open_objects.empty() &&
             !open_objects.back().insert(parsed.get<std::string>()).second)
      throw InvalidInput(path.string() + ": key '" + parsed.get<std::string>() + "' appears twice in the same object");
    return true;
  };
  try {
    return json::parse(s.str(), check);
  } catch (const json::parse_error& e) {
    // nlohmann's message carries the line and column.
    std::string what = e.what();
    const std::string prefix = "[json.exception.parse_error.101] ";
    if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
    throw InvalidInput(path.string() + ": invalid JSON: " + what);
  } catch (const json::exception& e) {
    throw InvalidInput(path.string() + ": invalid JSON: " + e.what());  // e.g. a number overflowing double
  }
}

void parse_environment(const json& j, const Keys& k, Environment& env) {
  const std::string key = "environment";
  k.require_object(j, key);
  if (!j.contains("type")) k.fail(key, "missing 'type' (fixed_sun or orbit)");
  const std::string type = k.string(j, key, "type");
  if (type == "fixed_sun") {
    env.type = EnvironmentType::fixed_sun;
    k.only_keys(j, key, {"type", "sun_direction", "solar_flux"}, " for type fixed_sun");
    if (j.contains("sun_direction")) {
      const json& d = j.at("sun_direction");
      if (!d.is_array() || d.size() != 3) k.fail(key + ".sun_direction", "must be an array of 3 numbers");
      Eigen::Vector3d v;
      for (int i = 0; i < 3; ++i) {
        if (!d[i].is_number() || !std::isfinite(d[i].get<double>())) k.fail(key + ".sun_direction", "must be an array of 3 finite numbers");
        v[i] = d[i].get<double>();
      }
      if (!(v.norm() > 0)) k.fail(key + ".sun_direction", "must not be the zero vector");
      env.sun_direction = v.normalized();
    }
    if (j.contains("solar_flux")) env.solar_flux_W_per_m2 = k.number_in(j, key, "solar_flux", 0, 1e7, false, " W/m^2");
  } else if (type == "orbit") {
    env.type = EnvironmentType::orbit;
    k.only_keys(j, key, {"type", "altitude_km", "inclination_deg", "raan_deg", "day_of_year", "attitude", "albedo", "earth_ir_flux"},
                " for type orbit");
    if (j.contains("altitude_km")) env.altitude_km = k.number_in(j, key, "altitude_km", 0, 1e6, true, " km");
    if (j.contains("inclination_deg")) env.inclination_deg = k.number_in(j, key, "inclination_deg", 0, 180, false, " deg");
    if (j.contains("raan_deg")) env.raan_deg = k.number_in(j, key, "raan_deg", -360, 360, false, " deg");
    if (j.contains("day_of_year")) env.day_of_year = static_cast<int>(k.integer(j, key, "day_of_year", 1, 366));
    if (j.contains("attitude")) {
      const std::string a = k.string(j, key, "attitude");
      if (a == "nadir") env.attitude = Attitude::nadir;
      else if (a == "sun") env.attitude = Attitude::sun;
      else if (a == "inertial") env.attitude = Attitude::inertial;
      else k.fail(key + ".attitude", "unknown attitude '" + a + "' (known: nadir, sun, inertial)");
    }
    if (j.contains("albedo")) env.albedo = k.number_in(j, key, "albedo", 0, 1, false, "");
    if (j.contains("earth_ir_flux")) env.earth_ir_flux_W_per_m2 = k.number_in(j, key, "earth_ir_flux", 0, 1e4, false, " W/m^2");
  } else {
    k.fail(key + ".type", "unknown environment type '" + type + "' (known: fixed_sun, orbit)");
  }
}

void parse_analysis(const json& j, const Keys& k, Analysis& a) {
  const std::string key = "analysis";
  k.require_object(j, key);
  if (!j.contains("type")) k.fail(key, "missing 'type' (steady or transient_orbit)");
  const std::string type = k.string(j, key, "type");
  if (type == "steady") {
    a.type = AnalysisType::steady;
    k.only_keys(j, key, {"type"}, " for type steady");
  } else if (type == "transient_orbit") {
    a.type = AnalysisType::transient_orbit;
    k.only_keys(j, key, {"type", "steps_per_orbit", "orbits", "time_tolerance_K"}, " for type transient_orbit");
    if (j.contains("steps_per_orbit")) a.steps_per_orbit = static_cast<int>(k.integer(j, key, "steps_per_orbit", 4, 1000000));
    if (j.contains("orbits")) a.orbits = static_cast<int>(k.integer(j, key, "orbits", 1, 10000));
    if (j.contains("time_tolerance_K")) a.time_tolerance_K = k.number_in(j, key, "time_tolerance_K", 0.0, 100.0, true, "K");
  } else {
    k.fail(key + ".type", "unknown analysis type '" + type + "' (known: steady, transient_orbit)");
  }
}

// Model files and load case files alike: an orbit transient needs an orbit.
void check_analysis_fits_environment(const Analysis& a, const Environment& e, const Keys& k) {
  if (a.type == AnalysisType::transient_orbit && e.type != EnvironmentType::orbit)
    k.fail("analysis.type", "transient_orbit needs an environment of type orbit (there is no orbit period otherwise)");
}

void parse_radiation(const json& j, const Keys& k, RadiationSettings& r) {
  const std::string key = "radiation";
  k.require_object(j, key);
  k.only_keys(j, key, {"rays_per_face", "min_rays_per_node", "seed"});
  // One side emits at most max(rays_per_face, min_rays_per_node) rays and the Sobol table
  // holds that many 16-byte points: 1e7 keeps it at 160 MB (40x the default
  // min_rays_per_node), where 1e9 would ask for 16 GB.
  constexpr long long kMaxRaysPerSide = 10000000;
  if (j.contains("rays_per_face")) r.rays_per_face = static_cast<int>(k.integer(j, key, "rays_per_face", 1, kMaxRaysPerSide));
  if (j.contains("min_rays_per_node"))
    r.min_rays_per_node = static_cast<int>(k.integer(j, key, "min_rays_per_node", 0, kMaxRaysPerSide));
  if (j.contains("seed")) {
    const json& s = j.at("seed");
    if (!s.is_number_unsigned() && !(s.is_number_integer() && s.get<long long>() >= 0))
      k.fail("radiation.seed", "must be an integer >= 0, got " + s.dump());
    r.seed = s.get<std::uint64_t>();
  }
}

ThermalModel model_from_json(const fs::path& path, const MeshReadOptions& options, bool allow_unknown_keys) {
  const std::string file = path.string();
  const Keys k(file, allow_unknown_keys);
  const json j = read_json(path);
  k.require_object(j, "");
  if (!j.contains("mesh") && j.contains("environment") && !j.contains("nodes") && !j.contains("materials"))
    k.fail("", "this looks like a load case file (environment/analysis only, no mesh): give it to "
               "`thermodec reduce MODEL --case FILE`; a model file needs a 'mesh' key");
  for (const auto& item : j.items()) {
    static const std::vector<std::string> known = {"mesh", "unit_scale", "materials", "default_material", "nodes",
                                                   "conductances", "environment", "analysis", "radiation", "description"};
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

  // Materials, in file order.
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

  // The mesh: its groups are the nodes.
  model.mesh = read_mesh(model.mesh_path, options);
  model.mesh.V *= model.unit_scale;
  ensure_nodes(model.mesh);
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
                               "sampling_boost"});
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
      if (v.contains("fixed_temperature")) node.fixed_temperature_K = k.number_in(v, key, "fixed_temperature", 1, 1e5, false, " K");
      if (v.contains("sampling_boost")) {
        const json& b = v.at("sampling_boost");
        const std::string bk = key + ".sampling_boost";
        k.require_object(b, bk);
        k.only_keys(b, bk, {"ir", "loads"});
        if (b.contains("ir")) node.sampling_boost.ir = k.number_in(b, bk, "ir", 1, 1e4, false, "");
        if (b.contains("loads")) node.sampling_boost.loads = k.number_in(b, bk, "loads", 1, 1e4, false, "");
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
  if (j.contains("environment")) parse_environment(j.at("environment"), k, model.environment);
  if (j.contains("analysis")) parse_analysis(j.at("analysis"), k, model.analysis);
  check_analysis_fits_environment(model.analysis, model.environment, k);
  if (j.contains("radiation")) parse_radiation(j.at("radiation"), k, model.radiation);
  return model;
}

const char* attitude_name(Attitude a) {
  switch (a) {
    case Attitude::nadir: return "nadir";
    case Attitude::sun: return "sun";
    case Attitude::inertial: return "inertial";
  }
  return "nadir";
}

}  // namespace

ThermalModel load_model(const fs::path& path, const MeshReadOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError(path.string() + ": no such file");
  if (is_mesh_path(path)) return model_from_bare_mesh(path, options, nullptr);
  if (lower_extension(path) != ".json")
    throw InvalidInput(path.string() + ": a model is a .json model file or a .obj, .ply or .stl mesh");
  return model_from_json(path, options, false);
}

ThermalModel load_model(const fs::path& path, const ModelLoadOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError(path.string() + ": no such file");
  if (is_mesh_path(path)) return model_from_bare_mesh(path, options.mesh, options.clean_bare_mesh ? &options.cleanup : nullptr);
  if (lower_extension(path) != ".json")
    throw InvalidInput(path.string() + ": a model is a .json model file or a .obj, .ply or .stl mesh");
  return model_from_json(path, options.mesh, options.allow_unknown_keys);
}

ThermalModel load_model(const fs::path& path) { return load_model(path, ModelLoadOptions{}); }

LoadCase own_case(const ThermalModel& model, const std::string& name) {
  return LoadCase{name, model.environment, model.analysis};
}

LoadCase load_case(const fs::path& path, const ThermalModel& base) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError(path.string() + ": no such file");
  const Keys k(path.string());
  const json j = read_json(path);
  k.require_object(j, "");
  k.only_keys(j, "", {"name", "description", "environment", "analysis"}, " in a load case file");
  LoadCase c = own_case(base, path.stem().string());
  if (j.contains("name")) c.name = k.string(j, "", "name");
  if (j.contains("environment")) parse_environment(j.at("environment"), k, c.environment);
  if (j.contains("analysis")) parse_analysis(j.at("analysis"), k, c.analysis);
  check_analysis_fits_environment(c.analysis, c.environment, k);
  return c;
}

ThermalModel with_case(const ThermalModel& model, const LoadCase& c) {
  ThermalModel m = model;
  m.environment = c.environment;
  m.analysis = c.analysis;
  return m;
}

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
    v["power"] = node.power_W;
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
  const Environment& e = model.environment;
  if (e.type == EnvironmentType::fixed_sun)
    j["environment"] = {{"type", "fixed_sun"},
                        {"sun_direction", {e.sun_direction.x(), e.sun_direction.y(), e.sun_direction.z()}},
                        {"solar_flux", e.solar_flux_W_per_m2}};
  else
    j["environment"] = {{"type", "orbit"},          {"altitude_km", e.altitude_km}, {"inclination_deg", e.inclination_deg},
                        {"raan_deg", e.raan_deg},   {"day_of_year", e.day_of_year}, {"attitude", attitude_name(e.attitude)},
                        {"albedo", e.albedo},       {"earth_ir_flux", e.earth_ir_flux_W_per_m2}};
  if (model.analysis.type == AnalysisType::steady)
    j["analysis"] = {{"type", "steady"}};
  else {
    j["analysis"] = {{"type", "transient_orbit"}, {"steps_per_orbit", model.analysis.steps_per_orbit}, {"orbits", model.analysis.orbits}};
    if (model.analysis.time_tolerance_K != Analysis{}.time_tolerance_K) j["analysis"]["time_tolerance_K"] = model.analysis.time_tolerance_K;
  }
  j["radiation"] = {{"rays_per_face", model.radiation.rays_per_face},
                    {"min_rays_per_node", model.radiation.min_rays_per_node},
                    {"seed", model.radiation.seed}};

  MeshWriteOptions mesh_options;
  mesh_options.protected_inputs = {json_path};
  write_mesh(mesh_path, mesh, mesh_options);
  write_text_atomically(json_path, j.dump(2) + "\n", {mesh_path});
}

}  // namespace thermodec
