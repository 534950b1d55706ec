#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/mesh/io.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/nodes/load_model.h"

namespace thermodec::cli {
namespace {

namespace fs = std::filesystem;

struct DecimateArgs {
  std::string model;
  std::string output;
  double ratio = -1;
  std::string node_ratios;
  DecimationOptions options;
  std::string collapse_cost = "geometric";
};

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

// {"node name": ratio, ...} (nodes not listed keep all faces) or [ratio per node].
Eigen::VectorXd read_node_ratios(const fs::path& path, const std::vector<std::string>& names) {
  // A FIFO or device would block or never end: like model and case files, a regular file only.
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw IOError(path.string() + ": not a regular file (a folder, device or FIFO)");
  if (fs::is_regular_file(status) && fs::file_size(path, ec) > (std::uintmax_t{64} << 20))
    throw IOError(path.string() + ": more than 64 MiB, too large for a node ratio file");
  std::ifstream in(path);
  if (!in) throw IOError(path.string() + ": cannot open");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(path.string() + ": not valid JSON: " + e.what());
  }
  Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<int>(names.size()));
  auto number = [&path](const nlohmann::json& v, const std::string& key) {
    if (!v.is_number()) throw InvalidInput(path.string() + ": '" + key + "' must be a number");
    const double x = v.get<double>();
    if (!(x >= 0 && x <= 1)) throw InvalidInput(path.string() + ": '" + key + "' must be in [0, 1]");
    return x;
  };
  if (j.is_array()) {
    if (j.size() != names.size())
      throw InvalidInput(path.string() + ": " + std::to_string(j.size()) + " ratios for " +
                         std::to_string(names.size()) + " nodes");
    for (size_t i = 0; i < j.size(); ++i) r[static_cast<int>(i)] = number(j[i], "[" + std::to_string(i) + "]");
  } else if (j.is_object()) {
    for (const auto& item : j.items()) {
      const auto it = std::find(names.begin(), names.end(), item.key());
      if (it == names.end()) throw InvalidInput(path.string() + ": unknown node '" + item.key() + "'");
      r[static_cast<int>(it - names.begin())] = number(item.value(), item.key());
    }
  } else {
    throw InvalidInput(path.string() + ": expected an object {node: ratio} or an array of ratios");
  }
  return r;
}

void run_decimate(const DecimateArgs& args) {
  ThermalModel model = load_model(args.model, model_load_options());
  // Outputs checked before the work: extension, folder, and every input (model, mesh, ratios).
  std::vector<fs::path> inputs{args.model, model.mesh_path};
  if (!args.node_ratios.empty()) inputs.push_back(args.node_ratios);
  {
    const fs::path out(args.output);
    check_output_file(out, "-o", {".json", ".obj", ".ply", ".stl"}, inputs);
    fs::path other = out;
    other.replace_extension(out.extension() == ".json" ? ".obj" : ".json");
    if (out.extension() != ".stl") check_output_file(other, "-o (companion file)", {}, inputs);
  }
  const Mesh& mesh = model.mesh;
  DecimationOptions options = args.options;
  options.collapse_cost = args.collapse_cost == "radiative" ? CollapseCostKind::radiative : CollapseCostKind::geometric;
  DecimationResult r;
  if (!args.node_ratios.empty()) {
    r = decimate_nodes(mesh, read_node_ratios(args.node_ratios, mesh.node_names), options);
  } else {
    r = decimate_to_global_ratio(mesh, args.ratio, options);
  }
  std::cout << fmt::format("{}: {} -> {} faces ({:.1f} % removed) in {} collapses\n", args.model,
                           mesh.num_faces(), r.mesh.num_faces(),
                           100.0 * (1.0 - static_cast<double>(r.mesh.num_faces()) / mesh.num_faces()),
                           r.collapses);
  std::cout << fmt::format("{:<16} {:>8} {:>8} {:>8} {:>6} {:>14} {:>8}\n", "node", "before", "target", "after",
                           "free", "area change %", "reached");
  for (size_t n = 0; n < r.nodes.size(); ++n) {
    const auto& s = r.nodes[n];
    const std::string name = n < mesh.node_names.size() ? mesh.node_names[n] : "(unassigned)";
    std::cout << fmt::format("{:<16} {:>8} {:>8} {:>8} {:>6} {:>14.4f} {:>8}\n", name, s.faces_before, s.target_faces,
                             s.faces_after, s.faces_removed_free, 100.0 * s.relative_area_change(),
                             s.reached ? std::string("yes") : std::string("no: ") + collapse_block_name(s.stopped_by()));
  }
  double worst_volume = 0;
  for (size_t k = 0; k < r.closed_volume_before_m3.size(); ++k)
    if (r.closed_volume_before_m3[k] != 0)
      worst_volume = std::max(worst_volume, std::abs(r.closed_volume_after_m3[k] / r.closed_volume_before_m3[k] - 1.0));
  std::cout << fmt::format("closed parts: {}, largest relative volume change {:.4f} %\n",
                           r.closed_volume_before_m3.size(), 100.0 * worst_volume);
  model.mesh = std::move(r.mesh);

  const fs::path out(args.output);
  const std::string ext = out.extension().string();
  fs::path json = out, mesh_out = out;
  if (ext == ".json")
    mesh_out.replace_extension(".obj");
  else
    json.replace_extension(".json");
  for (const fs::path& p : {json, mesh_out})
    for (const fs::path& in : inputs)
      if (!in.empty() && same_file(p, in)) throw InvalidInput(p.string() + ": refusing to overwrite an input file");
  if (ext == ".stl") {
    MeshWriteOptions w;
    w.protected_inputs = inputs;
    write_mesh(out, model.mesh, w);
    std::cout << "wrote " << out.string() << " (STL keeps geometry only; no model written)\n";
    return;
  }
  model.certificate.reset();  // a changed mesh no longer is the verified one
  save_model(model, json, mesh_out);
  std::cout << "wrote " << json.string() << " and " << mesh_out.string() << "\n";
}

}  // namespace

void add_decimate(CLI::App& app) {
  auto args = std::make_shared<DecimateArgs>();
  auto* sub = app.add_subcommand(
      "decimate",
      "thermodec decimate MODEL (--ratio R | --node-ratios FILE.json) -o OUT: node-preserving,\n"
      "area-preserving decimation of the shared mesh. A ratio is the fraction of faces REMOVED\n"
      "(0 = keep all, 0.9 = keep 10 %). --ratio applies the paper's global rule (nodes smallest\n"
      "first, deficits carried to the next); --node-ratios reads {\"node\": ratio} or [ratios].\n"
      "Faces never change node or material, interfaces are coarsened only along themselves,\n"
      "node areas and closed volumes stay within the stated tolerances. OUT.json writes the\n"
      "model and OUT.obj; OUT.obj/.ply writes the mesh and OUT.json.");
  sub->add_option("MODEL", args->model, "model file (.json) or mesh (.obj .ply .stl)")->required();
  sub->add_option("-o,--output", args->output, "output model (.json) or mesh (.obj .ply .stl)")->required();
  auto* ratio = sub->add_option("--ratio", args->ratio, "global fraction of faces to remove, in [0, 1)")
                    ->check(CLI::Range(0.0, 0.999999));
  auto* per_node = sub->add_option("--node-ratios", args->node_ratios, "JSON file of per-node ratios");
  ratio->excludes(per_node);
  per_node->excludes(ratio);
  sub->add_option("--max-area-change", args->options.max_relative_area_change,
                  "bound on each node's relative area change (a radiating node moves by dT = -T dA/4A: "
                  "0.005 is ~0.35 K at 280 K; `reduce` derives its bound from the tolerance)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--max-volume-change", args->options.max_relative_volume_change,
                  "bound on each closed component's relative volume change")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--volume-placement{false}", args->options.area_neutral_placement,
               "place collapsed vertices where volume is preserved (Lindstrom-Turk) instead of where the "
               "node's area is (the default: area is what radiation sees; volumes still stay within "
               "--max-volume-change)");
  sub->add_flag("--tube-sections", args->options.collapse_tube_sections,
               "on thin tubes (struts, ribs, cables) remove whole cross-sections at once: reaches much "
               "further on bent thin tubes, keeps their area and volume (off by default, and in `reduce`: "
               "measured to move thin ribs' temperatures more than single collapses; docs/decimation.md)");
  sub->add_option("--collapse-cost", args->collapse_cost,
                  "ranking of the collapses: geometric (Lindstrom-Turk volume and shape) or radiative (also "
                  "each node's projected area over all directions, which radiation sees; docs/decimation.md)")
      ->check(CLI::IsMember({"geometric", "radiative"}))
      ->capture_default_str();
  sub->add_option("--max-normal-deviation", args->options.max_normal_deviation_deg,
                  "refuse a collapse that turns a face by more than this [degrees]")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 179.0));
  sub->add_option("--projected-area-budget", args->options.projected_area_budget,
                  "let faces turn past --max-normal-deviation (up to --max-fold) while the summed change of their "
                  "area vectors stays within this multiple of --max-area-change times the node's area: it bounds "
                  "the node's projected-area change in every direction (0 = per-face check only; `reduce` uses 1; "
                  "docs/decimation.md)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--max-fold", args->options.max_fold_deg,
                  "with --projected-area-budget: no face turns by more than this [degrees], whatever its area")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 179.0));
  sub->add_option("--projected-area-cap", args->options.projected_area_cap,
                  "keep each node's projected area in 64 directions within this multiple of --max-area-change times "
                  "its area of its input; the budget then no longer refuses (0 = off; `reduce` uses 10; "
                  "docs/decimation.md)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--restore-areas", args->options.restore_node_areas,
               "with --projected-area-cap: a collapse past a node's area bound may run when offsets of the node's "
               "free vertices restore its area (`reduce` does this; docs/decimation.md)");
  sub->add_flag("--release-contacts", args->options.release_contacts,
               "a flat region that a part only touches (a sheet standing on a panel, a part touching a flat face "
               "at a point) drops the contact's vertices and may go down to its outline's triangles; the touching "
               "part keeps them, so the output is no longer conforming there (`reduce` does this; "
               "docs/decimation.md)");
  sub->add_option("--near-contact", args->options.near_contact_fraction,
                  "freeze a vertex lying within this fraction of its shortest edge of a nearly parallel face of another "
                  "node (a hinge end in the plane of its wall, a bracket millimetres off a panel): the exchange across such a gap "
                  "is decided at the gap's scale (0 = off; `reduce` uses 0.05; docs/decimation.md, \"Near contacts\")")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--max-kink", args->options.max_kinked_contour_deviation,
                  "with --projected-area-budget: a contour vertex up to this deviation (relative to the new segment) "
                  "may go when its nodes pay the outline's swept area from the budget")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--contour-deviation", args->options.max_contour_deviation,
                  "max deviation of a removed interface vertex, relative to the new segment")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->callback([args, ratio, per_node] {
    run_guarded([&] {
      if (ratio->count() == 0 && per_node->count() == 0) throw InvalidInput("decimate: give --ratio or --node-ratios");
      if (args->options.restore_node_areas && !(args->options.projected_area_cap > 0))
        throw InvalidInput("decimate: --restore-areas needs --projected-area-cap > 0 (the cap bounds what the offsets move)");
      run_decimate(*args);
    });
  });
}

}  // namespace thermodec::cli
