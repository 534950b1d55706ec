// thermodec viewfactors MODEL --json OUT: node view factors and IR radiative couplings.
#include <fmt/core.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/common/version.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec::cli {
namespace {

struct ViewFactorsOptions {
  std::string model;
  std::string json;
  int rays = -1;  // -1 = the model's radiation.rays_per_face
  long long seed = -1;
  bool two_sided = false;
};

nlohmann::ordered_json matrix(const Eigen::MatrixXd& m) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int i = 0; i < m.rows(); ++i) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (int j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::ordered_json vector(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

void run(const ViewFactorsOptions& o) {
  ThermalModel model = load_model(o.model, model_load_options());
  if (o.two_sided)  // thin sheets everywhere: the robust reading of open or badly oriented meshes
    for (int f = 0; f < model.mesh.num_faces(); ++f)
      if (model.mesh.face_back_material[f] < 0) model.mesh.face_back_material[f] = model.mesh.face_material[f];
  check_output_file(o.json, "--json", {".json"}, {o.model, model.mesh_path});
  RadiationSettings settings = model.radiation;
  if (o.rays != -1) settings.rays_per_face = o.rays;
  if (o.seed != -1) settings.seed = static_cast<std::uint64_t>(o.seed);
  settings.planar_strata = ModelSimulationSettings{}.planar_strata;  // the rows `simulate` computes
  model.radiation = settings;
  guard_simulation_cost("viewfactors", check_simulation_cost(model, {}, {}, SimulationCostScope::view_factors), false);
  const auto t0 = std::chrono::steady_clock::now();
  const NodeCouplings c = radiative_couplings(model, settings);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  nlohmann::ordered_json j;
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (const auto& n : model.nodes) names.push_back(n.name);
  j["schema_version"] = kInfoSchemaVersion;
  j["thermodec_version"] = kThermodecVersion;
  j["model"] = o.model;
  j["nodes"] = names;
  // Radiating area: a two-sided face radiates from both sides and counts twice (`info` counts
  // each face once).
  j["area_m2"] = vector(c.area_m2);
  j["area_note"] = "radiating area: two-sided faces count both sides (thermodec info counts each face once)";
  j["view_factors"] = matrix(c.view_factors);
  j["to_space"] = vector(c.to_space);
  j["radiative_couplings_m2"] = matrix(c.radiative_couplings_m2);
  j["to_space_couplings_m2"] = vector(c.to_space_couplings_m2);
  j["standard_error"] = {{"view_factors", matrix(c.view_factors_standard_error)},
                         {"radiative_couplings_m2", matrix(c.radiative_couplings_standard_error)},
                         {"to_space", vector(c.to_space_standard_error)},
                         {"to_space_couplings_m2", vector(c.to_space_couplings_standard_error)}};
  const CouplingDiagnostics& d = c.diagnostics;
  j["settings"] = {{"rays_per_face", settings.rays_per_face}, {"seed", settings.seed}};
  j["diagnostics"] = {{"surface_sides", d.surface_sides},
                      {"rays_traced", d.rays_traced},
                      {"untraceable_faces", d.untraceable_faces},
                      {"back_hits_on_one_sided", d.back_hits_on_one_sided},
                      {"unassigned_area_m2", d.unassigned_area_m2},
                      {"view_factor_asymmetry_sigma", d.view_factor_asymmetry_sigma},
                      {"coupling_asymmetry_relative", d.coupling_asymmetry_relative},
                      {"coupling_asymmetry_sigma", d.coupling_asymmetry_sigma},
                      {"non_reciprocal_pairs", d.non_reciprocal_pairs},
                      {"view_factor_closure_error", d.view_factor_closure_error},
                      {"coupling_closure_error", d.coupling_closure_error},
                      {"gebhart_closure_error", d.gebhart_closure_error},
                      {"gebhart_iterations", d.gebhart_iterations},
                      {"seconds", seconds}};
  std::vector<std::filesystem::path> inputs{o.model};
  if (!model.mesh_path.empty()) inputs.push_back(model.mesh_path);
  write_text_atomically(o.json, j.dump(1) + "\n", inputs);

  fmt::print("{} nodes, {} radiating sides, {} rays in {:.2f} s ({:.1f} Mrays/s)\n", model.nodes.size(),
             d.surface_sides, d.rays_traced, seconds, d.rays_traced / seconds * 1e-6);
  fmt::print("reciprocity before enforcing: view factors {:.2f} sigma, couplings {:.2g} relative ({:.2f} sigma)\n",
             d.view_factor_asymmetry_sigma, d.coupling_asymmetry_relative, d.coupling_asymmetry_sigma);
  fmt::print("closure: view factors {:.2g}, couplings {:.2g} (corrected on GR_ii), Gebhart {:.2g} after {} sweeps\n",
             d.view_factor_closure_error, d.coupling_closure_error, d.gebhart_closure_error, d.gebhart_iterations);
  if (d.untraceable_faces) fmt::print("{} zero-area or non-finite faces left out\n", d.untraceable_faces);
  if (d.back_hits_on_one_sided)
    fmt::print("{} rays passed through the back of a one-sided face (open or inconsistently oriented mesh?)\n",
               d.back_hits_on_one_sided);
  if (d.view_factor_asymmetry_sigma > 6.0)
    fmt::print("warning: the raw view factors are not reciprocal ({:.0f} sigma): the mesh is probably open, "
               "inconsistently oriented, self-intersecting or has coincident faces{}\n",
               d.view_factor_asymmetry_sigma, o.two_sided ? "" : " (try --two-sided)");
  if (d.non_reciprocal_pairs)
    fmt::print("{} node pairs not reciprocal beyond {:.0f} pooled standard errors (geometry, not noise): their "
               "couplings depend on the ray counts\n", d.non_reciprocal_pairs, kNonReciprocalSigma);
  fmt::print("{:<20} {:>10} {:>10} {:>12}\n", "node", "area_m2", "F_space", "GR_space_m2");
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    fmt::print("{:<20} {:>10.4g} {:>10.4f} {:>12.4g}\n", model.nodes[i].name, c.area_m2[i], c.to_space[i],
               c.to_space_couplings_m2[i]);
  fmt::print("area_m2 is the radiating area: two-sided faces count both sides (info counts each face once)\n");
  fmt::print("wrote {}\n", o.json);
}

}  // namespace

void add_viewfactors(CLI::App& app) {
  auto opts = std::make_shared<ViewFactorsOptions>();
  auto* sub = app.add_subcommand(
      "viewfactors",
      "thermodec viewfactors MODEL --json OUT: node-to-node view factors and IR radiative couplings "
      "(Monte Carlo ray tracing, Gebhart factors) with their standard errors");
  sub->add_option("MODEL", opts->model, "model.json or mesh (.obj .ply .stl)")->required();
  sub->add_option("--json", opts->json, "output JSON file")->required();
  sub->add_option("--rays,--rays-per-face", opts->rays, "IR view-factor rays per face side (default: the model's)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--seed", opts->seed, "random seed (default: the model's radiation.seed)")->check(CLI::NonNegativeNumber);
  sub->add_flag("--two-sided", opts->two_sided,
                "treat every one-sided face as a two-sided sheet (its back radiating with its front material)");
  sub->callback([opts] { run_guarded([&] { run(*opts); }); });
}

}  // namespace thermodec::cli
