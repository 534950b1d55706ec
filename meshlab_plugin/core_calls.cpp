#include "core_calls.h"
#include "document_model.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <filesystem>
#include <map>

#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/common/atomic_write.h"
#ifdef THERMODEC_FILTER_REDUCE
#include "thermodec/reduction/merge_reduction.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/reduction/reduction_reference.h"
#include "thermodec/reduction/sensitivity.h"
#include "thermodec/report/plot.h"
#include "thermodec/report/reduction_report.h"
#endif
#include "thermodec/thermal/result_json.h"
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

// Whether the document's mesh is `model`'s own (MeshLab keeps coordinates in single
// precision): same faces in the same order on the same corners, each on its model node.
bool is_models_own_mesh(const thermodec::Mesh& doc, const thermodec::ThermalModel& model,
                        const std::vector<int>& model_node) {
  const thermodec::Mesh& m = model.mesh;
  if (m.num_faces() != doc.num_faces()) return false;
  for (int f = 0; f < m.num_faces(); ++f) {
    if (m.face_node[f] != model_node[doc.face_node[f]]) return false;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        if (double(float(m.V(m.F(f, k), c))) != doc.V(doc.F(f, k), c)) return false;
  }
  return true;
}

// One line on the defaults a document without a model file is simulated with.
std::string defaults_description(const thermodec::ThermalModel& model) {
  char buf[400];
  const thermodec::Material& mat = model.materials.at(model.default_material);
  const auto& env = model.environment;
  std::snprintf(buf, sizeof buf,
                "no model file: thermodec's defaults for a bare mesh: %s analysis, %s, coating '%s' "
                "(alpha %.2f, eps %.2f) on every face, no capacitance, power or conduction",
                model.analysis.type == thermodec::AnalysisType::steady ? "steady-state" : "orbit transient",
                env.type == thermodec::EnvironmentType::orbit
                    ? (std::to_string(int(env.altitude_km)) + " km circular orbit, inclination " +
                       std::to_string(int(env.inclination_deg)) + " deg, nadir pointing").c_str()
                    : "fixed sun",
                mat.name.c_str(), mat.absorptivity, mat.emissivity);
  return buf;
}

// The document's model with the model's own seed (document_model applies the request's).
thermodec::ThermalModel document_model_unseeded(const thermodec::Mesh& mesh, const std::vector<int>& node_ids,
                                                bool ids_index_model_nodes, const std::string& model_file,
                                                int rays_per_face, std::vector<int>& model_node,
                                                std::string& description) {
  const int doc_nodes = static_cast<int>(mesh.node_names.size());
  if (doc_nodes == 0 || mesh.num_faces() == 0)
    throw thermodec::InvalidInput("no nodes: the document mesh has no faces with a node");
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.face_node[f] < 0 || mesh.face_node[f] >= doc_nodes)
      throw thermodec::InvalidInput("face " + std::to_string(f) + " has no node");

  thermodec::ThermalModel model;
  model_node.assign(doc_nodes, -1);
  if (model_file.empty()) {
    model = default_model(mesh);
    for (int i = 0; i < doc_nodes; ++i) {
      model_node[i] = index_of_node(model, mesh.node_names[i]);
      if (model_node[i] < 0) model_node[i] = i;  // same order when names were not kept
    }
    description = defaults_description(model);
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
    description = model_file;
    if (is_models_own_mesh(mesh, model, model_node)) {
      description += " (its own mesh: exact coordinates and per-face coatings)";
      if (rays_per_face > 0) model.radiation.rays_per_face = rays_per_face;
      return model;
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
  }
  if (rays_per_face > 0) model.radiation.rays_per_face = rays_per_face;
  return model;
}

}  // namespace

// The thermal model of the document (see simulate_document): model_node[i] receives the model
// node of document node i. Shared with export_calls.cpp (document_model.h).
thermodec::ThermalModel document_model(const DocumentModelRequest& request, std::vector<int>& model_node,
                                       std::string& description) {
  thermodec::ThermalModel model = document_model_unseeded(*request.mesh, request.node_ids,
                                                          request.ids_index_model_nodes, request.model_file,
                                                          request.rays_per_face, model_node, description);
  if (request.seed >= 0) model.radiation.seed = static_cast<std::uint64_t>(request.seed);
  return model;
}

namespace {

#ifdef THERMODEC_FILTER_REDUCE
// Reduction and sensitivity change the mesh node by node: every model node must be exactly one
// document node, so that results map back. Returns document node of each model node.
std::vector<int> one_to_one(const std::vector<int>& model_node, const thermodec::ThermalModel& model) {
  std::vector<int> doc_node(model.nodes.size(), -1);
  for (std::size_t i = 0; i < model_node.size(); ++i) {
    if (doc_node[model_node[i]] >= 0)
      throw thermodec::InvalidInput("two document nodes are the model node '" + model.nodes[model_node[i]].name + "'");
    doc_node[model_node[i]] = static_cast<int>(i);
  }
  for (std::size_t n = 0; n < doc_node.size(); ++n)
    if (doc_node[n] < 0)
      throw thermodec::InvalidInput("the model node '" + model.nodes[n].name + "' has no faces in the document");
  return doc_node;
}
#endif

}  // namespace

void refuse_costly(const thermodec::SimulationCostCheck& check) {
  thermodec::refuse_costly_run(check, false, "run it with the CLI's --force (thermodec simulate MODEL --force)");
}

NodeTemperatures simulate_document(const DocumentModelRequest& request, const std::string& result_file) {
  const thermodec::Mesh& mesh = *request.mesh;
  const int doc_nodes = static_cast<int>(mesh.node_names.size());
  NodeTemperatures out;
  out.nodes = mesh.node_names;
  std::vector<int> model_node;
  thermodec::ThermalModel model = document_model(request, model_node, out.model_description);
  out.model_nodes.resize(doc_nodes);
  for (int i = 0; i < doc_nodes; ++i) out.model_nodes[i] = model.nodes[model_node[i]].name;

  thermodec::ModelSimulationSettings settings;
  settings.progress = request.progress;
  thermodec::apply_bare_mesh_ray_budgets(model, settings);  // as `thermodec simulate` (no-op for model files)
  refuse_costly(thermodec::check_front_end_simulation_cost(model, settings));
  const thermodec::FrontEndSimulation sim = thermodec::simulate_as_front_end(model, settings);
  if (sim.sampling) out.sampling = sim.sampling->describe(model.nodes);
  const thermodec::SimulationResult& r = sim.result;
  if (!result_file.empty()) {
    nlohmann::json j = thermodec::result_to_json(r);
    j["model"] = request.model_file;
    j["settings"] = {{"rays_per_face", model.radiation.rays_per_face}, {"seed", model.radiation.seed}};
    std::vector<fs::path> inputs;
    if (!request.model_file.empty()) inputs.push_back(request.model_file);
    thermodec::write_text_atomically(result_file, j.dump(1) + "\n", inputs);
  }
  out.transient = r.transient;
  out.times = static_cast<int>(r.times_s.size());
  out.orbits = r.orbits;
  out.periodicity_residual_K = r.periodicity_residual_K;
  for (int i = 0; i < doc_nodes; ++i) {
    const auto row = r.temperature_K.row(model_node[i]);
    out.min_K.push_back(row.minCoeff());
    out.mean_K.push_back(row.mean());
    out.max_K.push_back(row.maxCoeff());
    const Eigen::Index m = model_node[i];
    out.noise_K.push_back(m < r.noise_K.size() ? r.noise_K[m] : 0.0);
  }
  out.orbit_sampling_error_K = r.orbit_sampling_error_K;
  // Where the orbit's extremes occur: the first thing a thermal engineer checks against limits.
  out.coldest = static_cast<int>(std::min_element(out.min_K.begin(), out.min_K.end()) - out.min_K.begin());
  out.hottest = static_cast<int>(std::max_element(out.max_K.begin(), out.max_K.end()) - out.max_K.begin());
  out.seed = model.radiation.seed;
  out.rays_per_face = model.radiation.rays_per_face;
  return out;
}

#ifdef THERMODEC_FILTER_REDUCE
DocumentReduction reduce_document(const DocumentModelRequest& request, double tolerance_K,
                                  bool informed, const std::string& out_dir, bool plots,
                                  const std::vector<std::string>& case_files, bool merge_nodes) {
  std::vector<int> model_node;
  std::string description;
  thermodec::ThermalModel model = document_model(request, model_node, description);
  const std::vector<int> doc_node = one_to_one(model_node, model);

  thermodec::ReduceSettings settings;
  settings.tolerance_K = tolerance_K;
  settings.strategy = informed ? thermodec::ReductionStrategy::informed : thermodec::ReductionStrategy::uniform;
  settings.progress = request.progress;
  settings.reference.simulation.progress = nullptr;
  thermodec::apply_large_model_sweep(model, settings);  // as `thermodec reduce` does for this model
  for (const auto& f : case_files) settings.extra_cases.push_back(thermodec::load_case(f, model));
  refuse_costly(thermodec::check_simulation_cost(model, settings.reference.simulation, settings.extra_cases));
  const thermodec::ReductionRun run = merge_nodes ? thermodec::reduce_with_node_merging(model, settings, {})
                                                  : thermodec::reduce_model(model, settings);

  std::vector<fs::path> inputs;
  if (!request.model_file.empty()) inputs.push_back(request.model_file);
  DocumentReduction out;
  out.warnings = thermodec::write_reduction_outputs(run, out_dir, inputs, plots);
  out.summary = thermodec::reduction_summary(run);
  out.max_temperature_difference_K = run.max_temperature_difference_K;
  out.noise_floor_K = run.noise_floor_K;
  out.mesh = run.reduced.model.mesh;
  out.mesh.node_names = request.mesh->node_names;
  out.model_file = (fs::path(out_dir) / "model.json").string();
  // A merged node shows under its first member's document node.
  std::vector<int> doc_of_reduced;
  for (const thermodec::Node& nd : run.reduced.model.nodes) {
    std::vector<std::string> members;
    for (const auto& [name, into] : run.reduced.model.node_map)
      if (into == nd.name) members.push_back(name);
    const int original = index_of_node(model, members.empty() ? nd.name : members.front());
    doc_of_reduced.push_back(original >= 0 ? doc_node[original] : 0);
    if (members.size() > 1) out.merged.push_back({nd.name, members, doc_of_reduced.back()});
  }
  for (int f = 0; f < out.mesh.num_faces(); ++f) out.mesh.face_node[f] = doc_of_reduced[out.mesh.face_node[f]];
  return out;
}

DocumentSensitivity sensitivity_document(const DocumentModelRequest& request, double tolerance_K,
                                         const std::string& out_dir) {
  if (!(tolerance_K > 0) || !std::isfinite(tolerance_K))
    throw thermodec::InvalidInput("tolerance_K must be finite and > 0, got " + std::to_string(tolerance_K));
  std::vector<int> model_node;
  std::string description;
  thermodec::ThermalModel model = document_model(request, model_node, description);
  const std::vector<int> doc_node = one_to_one(model_node, model);

  // Same sweep as `thermodec reduce --strategy informed` (cap = 2 x tolerance).
  const thermodec::ReduceSettings defaults;
  refuse_costly(thermodec::check_simulation_cost(model, defaults.reference.simulation));
  if (request.progress) request.progress("reference simulation");
  const thermodec::ReductionReference reference(model, defaults.reference);
  thermodec::SensitivityOptions options = defaults.sensitivity;
  options.cap_K = defaults.sensitivity_cap_factor * tolerance_K;
  if (request.progress)
    options.progress = [&](int done, int total) {
      request.progress("sensitivity: " + std::to_string(done) + " of " + std::to_string(total) + " nodes");
    };
  const int n = static_cast<int>(model.nodes.size());
  const auto curves = thermodec::sensitivity_analysis(
      n, [&](const Eigen::VectorXd& r) { return reference.trial(r); }, options);

  DocumentSensitivity out;
  out.nodes = request.mesh->node_names;
  const int doc_nodes = static_cast<int>(out.nodes.size());
  out.ratios.resize(doc_nodes);
  out.max_abs_dT_K.resize(doc_nodes);
  out.faces_after.resize(doc_nodes);
  out.faces_before.assign(doc_nodes, 0);
  for (int m = 0; m < n; ++m) out.faces_before[doc_node[m]] = reference.faces_per_node()[m];
  for (const auto& c : curves) {
    const int d = doc_node[c.node];
    out.ratios[d] = c.ratios;
    out.max_abs_dT_K[d] = c.max_abs_dT_K;
    out.faces_after[d] = c.faces_after;
  }

  fs::create_directories(out_dir);
  std::ostringstream csv;
  csv << "node,faces_before,ratio,faces_after,max_abs_dT_K\n";
  nlohmann::json jcurves = nlohmann::json::array();
  for (int d = 0; d < doc_nodes; ++d) {
    for (std::size_t k = 0; k < out.ratios[d].size(); ++k)
      csv << out.nodes[d] << ',' << out.faces_before[d] << ',' << out.ratios[d][k] << ','
          << out.faces_after[d][k] << ',' << out.max_abs_dT_K[d][k] << '\n';
    jcurves.push_back({{"node", out.nodes[d]}, {"faces_before", out.faces_before[d]}, {"ratios", out.ratios[d]},
                       {"max_abs_dT_K", out.max_abs_dT_K[d]}, {"faces_after", out.faces_after[d]}});
  }
  const fs::path csv_path = fs::path(out_dir) / "sensitivity.csv";
  thermodec::write_text_atomically(csv_path, csv.str(), {});
  out.files.push_back(csv_path.string());
  const fs::path png = fs::path(out_dir) / "sensitivity.png";
  try {
    thermodec::plot_png("sensitivity", {{"tolerance_K", tolerance_K}, {"cap_K", options.cap_K}, {"curves", jcurves}}, png);
    out.files.push_back(png.string());
  } catch (const thermodec::Error& e) {
    out.warnings.push_back("sensitivity.png: " + std::string(e.what()));
  }
  return out;
}
#endif  // THERMODEC_FILTER_REDUCE

}  // namespace thermodec_meshlab
