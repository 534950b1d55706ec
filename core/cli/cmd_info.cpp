#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/common/version.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/printable.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/mesh_stats.h"
#include "thermodec/nodes/load_model.h"

namespace thermodec::cli {
namespace {

struct InfoArgs {
  std::string model;
  std::string json_out;
  double weld_tolerance = MeshReadOptions{}.weld_tolerance;
};

// Names and paths as they may be printed: the readers refuse control characters in names, and
// this keeps any that come another way (a file name) off the terminal.
std::string shown(const std::string& text) { return printable(text, 1000); }

std::string material_list(const ThermalModel& model, const std::vector<int>& ids) {
  std::string s;
  for (int m : ids) s += (s.empty() ? "" : ", ") + (m >= 0 ? shown(model.materials[m].name) : std::string("(none)"));
  return s;
}

void run_info(const InfoArgs& args) {
  MeshReadOptions read;
  read.weld_tolerance = args.weld_tolerance;
  read.drop_degenerate_faces = false;  // info reports them instead
  const ThermalModel model = load_model(args.model, model_load_options(read, false));
  if (!args.json_out.empty()) check_output_file(args.json_out, "--json", {".json"}, {args.model, model.mesh_path});
  const Mesh& mesh = model.mesh;
  const MeshStats s = mesh_stats(mesh);
  const auto counts = node_face_counts(mesh);
  const auto areas = node_areas_m2(mesh);
  const auto materials = node_materials(mesh);
  std::vector<int> two_sided(model.nodes.size(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.is_two_sided(f)) two_sided[mesh.face_node[f]] += 1;

  std::string out;
  auto line = [&](const std::string& key, const std::string& value) { out += fmt::format("{:<20}{}\n", key, value); };
  line("model", shown(args.model));
  line("mesh", shown(model.mesh_path.string()));
  line("faces", std::to_string(s.faces));
  // simulate, reduce and decimate clean a raw mesh before building its nodes (load_model.h).
  // info describes the file even where the cleanup refuses it (the other commands then stop).
  bool cleans = false;
  BareMeshCleanupReport cleanup;
  try {
    const ThermalModel cleaned = load_model(args.model, model_load_options());
    cleans = cleaned.mesh_cleanup.has_value();
    if (cleans) cleanup = *cleaned.mesh_cleanup;
    if (cleans)
      line("bare-mesh cleanup", fmt::format("on: simulate, reduce and decimate use {} faces, {} nodes",
                                            cleaned.mesh.num_faces(), cleaned.nodes.size()));
    if (cleans && cleanup.enclosing_shells)
      line("enclosed faces", fmt::format("{} inside {} closed parts, whose {} faces radiate from both sides",
                                         cleanup.enclosed_faces, cleanup.enclosing_shells,
                                         cleanup.shell_faces_made_two_sided));
    if (!cleans)
      line("bare-mesh cleanup", "off (grouped mesh, or a model file naming nodes or radiation)");
  } catch (const Error& e) {
    line("bare-mesh cleanup", "fails: " + shown(e.what()));
  }
  line("vertices", s.unreferenced_vertices ? fmt::format("{} ({} unreferenced)", s.vertices, s.unreferenced_vertices)
                                           : std::to_string(s.vertices));
  line("edges", std::to_string(s.edges));
  line("components", std::to_string(s.components));
  line("boundary edges", std::to_string(s.boundary_edges));
  line("non-manifold edges", std::to_string(s.non_manifold_edges));
  line("degenerate faces", std::to_string(s.degenerate_faces));
  line("area", fmt::format("{:.6g} m^2 (each face once, two-sided faces too)", s.area_m2));
  out += environment_analysis_text(model);
  line("materials", std::to_string(model.materials.size()));
  for (const auto& m : model.materials)
    out += fmt::format("  {:<18}absorptivity {:.3g}  emissivity {:.3g}\n", shown(m.name), m.absorptivity, m.emissivity);
  line("nodes", std::to_string(model.nodes.size()));
  std::size_t w = 4;
  for (const auto& n : model.nodes) w = std::max(w, shown(n.name).size());
  out += fmt::format("  {:<{}}  {:>8}  {:>12}  {}\n", "node", w, "faces", "area [m^2]", "material(s)");
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    std::string mats = material_list(model, materials[n]);
    if (two_sided[n]) mats += fmt::format("  [two-sided: {} faces]", two_sided[n]);
    out += fmt::format("  {:<{}}  {:>8}  {:>12.6g}  {}\n", shown(model.nodes[n].name), w, counts[n], areas[n], mats);
  }
  if (model.certificate) {  // a reduced model: its verification against the original
    line("certificate", "");
    for (const std::string& l : certificate_lines(*model.certificate)) out += "  " + l + "\n";
  }
  std::cout << out;

  if (!args.json_out.empty()) {
    nlohmann::ordered_json j;
    j["schema_version"] = kInfoSchemaVersion;
    j["thermodec_version"] = kThermodecVersion;
    j["model"] = args.model;
    j["mesh"] = model.mesh_path.string();
    j["faces"] = s.faces;
    j["bare_mesh_cleanup"] = cleans;
    if (cleans)
      j["enclosed"] = {{"faces", cleanup.enclosed_faces},
                       {"closed_parts", cleanup.enclosing_shells},
                       {"shell_faces_made_two_sided", cleanup.shell_faces_made_two_sided}};
    j["vertices"] = s.vertices;
    j["unreferenced_vertices"] = s.unreferenced_vertices;
    j["edges"] = s.edges;
    j["components"] = s.components;
    j["boundary_edges"] = s.boundary_edges;
    j["non_manifold_edges"] = s.non_manifold_edges;
    j["degenerate_faces"] = s.degenerate_faces;
    j["area_m2"] = s.area_m2;
    const auto settings = environment_analysis_json(model);
    for (const auto& [key, value] : settings.items()) j[key] = value;
    j["materials"] = nlohmann::ordered_json::array();
    for (const auto& m : model.materials)
      j["materials"].push_back({{"name", m.name}, {"absorptivity", m.absorptivity}, {"emissivity", m.emissivity}});
    j["nodes"] = nlohmann::ordered_json::array();
    for (std::size_t n = 0; n < model.nodes.size(); ++n) {
      nlohmann::ordered_json mats = nlohmann::ordered_json::array();
      for (int m : materials[n]) mats.push_back(m >= 0 ? model.materials[m].name : std::string());
      j["nodes"].push_back({{"name", model.nodes[n].name}, {"faces", counts[n]}, {"area_m2", areas[n]},
                            {"materials", mats}, {"two_sided_faces", two_sided[n]}});
    }
    if (model.certificate) j["certificate"] = certificate_json(*model.certificate);
    write_text_atomically(args.json_out, j.dump(2) + "\n", {args.model, model.mesh_path});
    std::cout << "statistics written to " << shown(args.json_out) << "\n";
  }
}

}  // namespace

void add_info(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  auto* sub = app.add_subcommand(
      "info",
      "Print mesh and thermal-node statistics of MODEL: faces, vertices, edge-connected components,\n"
      "boundary and non-manifold edges, degenerate faces, total area, materials, and per node its\n"
      "face count, area [m^2] and material(s). Degenerate faces are counted, not dropped.");
  sub->add_option("MODEL", args->model, "model file (.json, docs/model-format.md) or bare mesh (.obj .ply .stl)")
      ->required();
  sub->add_option("--json", args->json_out, "also write the statistics as JSON to this file");
  sub->add_option("--weld-tolerance", args->weld_tolerance,
                  "merge vertices closer than this [mesh file units]; < 0 disables (STL: exact duplicates)")
      ->capture_default_str();
  sub->callback([args] { run_guarded([&] { run_info(*args); }); });
}

}  // namespace thermodec::cli
