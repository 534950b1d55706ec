#include "thermodec/common/version.h"
#include "thermodec/report/reduction_report.h"

#include <cmath>
#include <cstdio>
#include <future>
#include <sstream>

#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/report/plot.h"

namespace thermodec {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json curve_json(const SensitivityCurve& c, const ReductionRun& run) {
  json j = {{"node", run.nodes[c.node].name},
          {"faces_before", run.nodes[c.node].faces_before},
          {"ratios", c.ratios},
          {"max_abs_dT_K", c.max_abs_dT_K},
          {"faces_after", c.faces_after},
          {"chosen_ratio", run.nodes[c.node].requested_ratio},
          {"predicted_ratio", run.nodes[c.node].predicted_ratio}};
  // (the ratio past the last sample where the node alone kept its faces; absent: none)
  if (std::isfinite(c.stalled_ratio)) j["stalled_alone_at_ratio"] = c.stalled_ratio;
  return j;
}

json mesh_panel(const Mesh& m, const std::string& title, const Eigen::VectorXd* value, const std::string& label) {
  json V = json::array(), F = json::array(), val = json::array();
  for (int v = 0; v < m.num_vertices(); ++v) V.push_back({m.V(v, 0), m.V(v, 1), m.V(v, 2)});
  for (int f = 0; f < m.num_faces(); ++f) {
    F.push_back({m.F(f, 0), m.F(f, 1), m.F(f, 2)});
    val.push_back(value ? (*value)[m.face_node[f]] : static_cast<double>(m.face_node[f]));
  }
  return {{"title", title}, {"vertices", V}, {"faces", F}, {"face_value", val},
          {"categorical", value == nullptr}, {"value_label", label}};
}

}  // namespace

json node_merging_json(const NodeMerging& m) {
  json steps = json::array();
  for (const NodeMergeStep& st : m.steps)
    steps.push_back({{"merged", st.first}, {"with", st.second}, {"pair_dT_K", st.pair_dT_K}, {"dT_K", st.dT_K},
                     {"nodes_after", st.nodes_after}, {"faces", st.faces}});
  json map = json::object();
  for (const auto& [original, merged] : m.node_map) map[original] = merged;
  json j = {{"nodes_before", m.nodes_before}, {"nodes_after", m.nodes_after}, {"kept", m.kept},
            {"candidates", m.candidates}, {"trials", m.trials}, {"budget_K", m.budget_K},
            {"small_budget_K", m.small_budget_K}, {"small_nodes", m.small_nodes}, {"dT_K", m.dT_K},
            {"decimation_tolerance_K", m.decimation_tolerance_K}, {"traced_dT_K", m.traced_dT_K},
            {"traced_simulations", m.traced_simulations}, {"merges", steps}, {"node_map", map},
            {"seconds", m.seconds}};
  if (!m.fallback.empty()) j["fallback"] = m.fallback;
  // What no merge can beat (reduction/merge_bound.h); a count no merge reaches has no finite cost.
  json least = json::array();
  for (const auto& [nodes, dT] : m.least_merge_dT_K)
    least.push_back({{"nodes", nodes}, {"dT_K", std::isfinite(dT) ? json(dT) : json(nullptr)}});
  j["bound"] = {{"fewest_nodes_at_budget", m.fewest_nodes_at_budget},
                {"fewest_nodes_at_tolerance", m.fewest_nodes_at_tolerance},
                {"apart_at_tolerance", m.apart_at_tolerance}, {"least_merge_dT_K", least}};
  return j;
}

json reduction_report_json(const ReductionRun& run) {
  json j;
  j["schema_version"] = kReportSchemaVersion;
  j["thermodec_version"] = kThermodecVersion;
  j["strategy"] = run.strategy;
  j["tolerance_K"] = run.tolerance_K;
  j["faces_before"] = run.faces_before;
  j["faces_after"] = run.faces_after;
  j["max_temperature_difference_K"] = run.max_temperature_difference_K;
  j["max_temperature_difference_at"] = {
      {"node", run.max_difference_node}, {"time_s", run.max_difference_time_s}, {"load_case", run.max_difference_case}};
  j["noise_floor_K"] = run.noise_floor_K;
  j["max_relative_area_change"] = run.max_relative_area_change;  // the decimator's node-area bound used
  if (!run.node_max_relative_area_change.empty())
    j["node_max_relative_area_change"] = run.node_max_relative_area_change;  // per node, in node order
  j["verified"] = "full recompute of the reduced model (no reuse) compared with the reference";
  // The guarantee: replicate pairs with seeds the search never used (docs/reduction.md).
  const VerificationStatistics& v = run.verification;
  j["verification"] = {{"max_abs_dT_K", v.max_abs_dT_K},
                       {"standard_error_K", v.standard_error_K},
                       {"upper_bound_K", v.upper_bound_K},
                       {"confidence", v.confidence},
                       {"replicates", v.replicates},
                       {"seeds", v.seeds},
                       {"search_tolerance_K", run.search_tolerance_K}};
  json cases = json::array();
  for (const auto& c : run.cases)
    cases.push_back({{"name", c.name}, {"noise_floor_K", c.noise_floor_K},
                     {"ray_record_bytes", c.ray_record_bytes}, {"ray_record_budget_bytes", c.ray_record_budget_bytes},
                     {"view_factor_bytes", c.view_factor_bytes}, {"earth_hit_bytes", c.earth_hit_bytes},
                     {"max_temperature_difference_K", c.max_temperature_difference_K},
                     {"max_temperature_difference_at", {{"node", c.max_difference_node}, {"time_s", c.max_difference_time_s}}}});
  j["load_cases"] = cases;
  json nodes = json::object();
  for (const auto& n : run.nodes) {
    nodes[n.name] = {{"faces_before", n.faces_before}, {"faces_after", n.faces_after}, {"ratio", n.ratio},
                     {"requested_ratio", n.requested_ratio}, {"predicted_ratio", n.predicted_ratio},
                     {"max_abs_dT_K", n.max_abs_dT_K}, {"area_before_m2", n.area_before_m2},
                     {"area_after_m2", n.area_after_m2}, {"target_faces", n.target_faces},
                     {"faces_removed", n.faces_before - n.faces_after}, {"stopped_by", n.stopped_by}};
    json blocked = json::object();
    for (const auto& [why, edges] : n.blocked_edges) blocked[why] = edges;
    nodes[n.name]["blocked_edges"] = blocked;
  }
  j["nodes"] = nodes;
  json curves = json::array();
  for (const auto& c : run.curves) curves.push_back(curve_json(c, run));
  j["sensitivity"] = curves;
  json pred = json::array();
  for (const auto& p : run.prediction)
    pred.push_back({{"target_K", p.target_K}, {"predicted_K", p.predicted_K}, {"real_K", p.real_K},
                    {"faces_after", p.faces_after}});
  j["predicted_vs_real"] = pred;
  json hist = json::array();
  for (const auto& h : run.outcome.history) {
    hist.push_back({{"action", h.action}, {"faces_after", h.result.faces_after},
                    {"max_abs_dT_K", h.result.max_abs_dT_K}, {"within_tolerance", h.within_tolerance},
                    {"superposition_predicted_K", h.predicted_K}});
    if (std::isfinite(h.anchored_predicted_K)) hist.back()["anchored_predicted_K"] = h.anchored_predicted_K;
  }
  j["history"] = hist;
  j["trials"] = run.trials;
  j["rays"] = {{"ir_rays_per_face", run.rays_per_face}, {"sun_rays_per_face", run.sun_rays_per_face}};
  nlohmann::json boosts = nlohmann::json::object();
  for (std::size_t k = 0; k < run.sampling_boost.size() && k < run.nodes.size(); ++k)
    if (run.sampling_boost[k] != Node::SamplingBoost{})
      boosts[run.nodes[k].name] = {{"ir", run.sampling_boost[k].ir}, {"loads", run.sampling_boost[k].loads}};
  j["rays"]["sampling_boost"] = boosts;
  if (run.mesh_cleanup) {
    const BareMeshCleanupReport& c = *run.mesh_cleanup;
    j["mesh_cleanup"] = {{"faces_in", c.faces_in},
                         {"faces_out", c.faces_out},
                         {"vertices_welded", c.vertices_welded},
                         {"degenerate_faces_dropped", c.degenerate_faces_dropped},
                         {"t_junctions_split", c.t_junctions_split},
                         {"faces_flipped", c.faces_flipped},
                         {"duplicate_faces_dropped", c.duplicate_faces_dropped},
                         {"back_to_back_pairs_merged", c.back_to_back_pairs_merged},
                         {"closed_parts", c.closed_components},
                         {"open_sheets", c.open_components},
                         {"open_sheet_faces_made_two_sided", c.open_sheet_faces_made_two_sided},
                         {"coincident_faces_dropped", c.coincident_faces_dropped},
                         {"coincident_area_dropped_m2", c.coincident_area_dropped_m2},
                         {"overlapping_sheet_faces_dropped", c.overlapping_sheet_faces_dropped},
                         {"overlapping_sheet_area_dropped_m2", c.overlapping_sheet_area_dropped_m2},
                         {"enclosing_shells", c.enclosing_shells},
                         {"shell_faces_made_two_sided", c.shell_faces_made_two_sided},
                         {"enclosed_faces", c.enclosed_faces}};
  }
  j["timings_s"] = {{"total", run.seconds_total}, {"noise_floor", run.seconds_noise},
                    {"sensitivity", run.seconds_sensitivity}, {"search", run.seconds_search},
                    {"verification", run.seconds_verification}};
  if (run.merging) j["node_merging"] = node_merging_json(*run.merging);
  j["peak_memory_bytes"] = run.peak_memory_bytes;  // this process's peak resident set (0: not measured)
  if (run.ranks > 1) j["mpi"] = {{"ranks", run.ranks}, {"peak_memory_bytes_other_ranks", run.peak_memory_bytes_other_ranks}};
  return j;
}

std::vector<std::string> write_reduction_outputs(const ReductionRun& run, const fs::path& out_dir,
                                                 const std::vector<fs::path>& protected_inputs, bool plots) {
  for (const auto& in : protected_inputs)
    for (const char* name : {"model.json", "reduced.obj", "report.json"})
      if (!in.empty() && same_file(out_dir / name, in))
        throw InvalidInput("output folder " + out_dir.string() + " would overwrite input " + in.string());
  std::error_code ec;
  // The verification travels with the reduced model (its exports repeat it in their headers).
  ThermalModel reduced = run.reduced.model;
  ModelCertificate cert;
  if (!protected_inputs.empty() && !protected_inputs.front().empty()) {
    const fs::path& original = protected_inputs.front();
    cert.original_model = fs::absolute(original, ec).string();
    cert.original_sha256 = file_sha256(original.string());
    if (protected_inputs.size() > 1 && !protected_inputs[1].empty() && !same_file(protected_inputs[1], original))
      cert.original_mesh_sha256 = file_sha256(protected_inputs[1].string());
  }
  cert.tolerance_K = run.tolerance_K;
  for (const auto& c : run.cases) cert.cases.push_back(c.name);
  cert.estimate_K = run.verification.max_abs_dT_K;
  cert.standard_error_K = run.verification.standard_error_K;
  cert.upper_bound_K = run.verification.upper_bound_K;
  cert.confidence = run.verification.confidence;
  cert.seeds = run.verification.seeds;
  cert.faces_before = run.faces_before;
  cert.faces_after = run.faces_after;
  reduced.certificate = cert;
  save_model(reduced, out_dir / "model.json", out_dir / "reduced.obj");
  json report = reduction_report_json(run);
  if (!protected_inputs.empty()) report["input_model"] = fs::absolute(protected_inputs.front(), ec).string();
  write_text_atomically(out_dir / "report.json", report.dump(2) + "\n", protected_inputs);

  std::vector<std::string> warnings;
  if (!plots) return warnings;
  // The plots are drawn side by side, each by its own python process (the mesh view of a 20k-face
  // model alone takes ~5 s); a plot that fails is a warning, never a failed reduction.
  std::vector<std::future<std::string>> drawn;
  auto plot = [&](const std::string& kind, json data, const std::string& file) {
    drawn.push_back(std::async(std::launch::async, [kind, data = std::move(data), path = out_dir / file, file] {
      try {
        plot_png(kind, data, path);
        return std::string();
      } catch (const Error& e) {
        return file + ": " + e.what();
      }
    }));
  };
  if (!run.curves.empty()) {
    json curves = json::array();
    for (const auto& c : run.curves) curves.push_back(curve_json(c, run));
    plot("sensitivity", {{"tolerance_K", run.tolerance_K}, {"noise_floor_K", run.noise_floor_K}, {"curves", curves}},
         "sensitivity.png");
  }
  if (!run.prediction.empty()) {
    json pts = json::array();
    for (const auto& p : run.prediction)
      pts.push_back({{"target_K", p.target_K}, {"predicted_K", p.predicted_K}, {"real_K", p.real_K},
                     {"label", std::to_string(p.faces_after) + " f"}});
    // The search after the prediction (back-off, push) and the verified final model, so the
    // plot shows how a prediction over the tolerance was brought back within it.
    json steps = json::array();
    for (const auto& h : run.outcome.history) {
      json step = {{"action", h.action}, {"max_abs_dT_K", h.result.max_abs_dT_K}, {"within_tolerance", h.within_tolerance},
                   {"faces_after", h.result.faces_after}};
      if (std::isfinite(h.predicted_K)) step["superposition_predicted_K"] = h.predicted_K;
      steps.push_back(step);
    }
    plot("predicted_vs_real",
         {{"points", pts}, {"tolerance_K", run.tolerance_K}, {"history", steps},
          {"final", {{"real_K", run.max_temperature_difference_K}, {"faces_after", run.faces_after}}}},
         "predicted_vs_real.png");
  }
  {
    json ref = json::object(), red = json::object();
    const auto& a = run.reference;
    const auto& b = run.reduced.result;
    for (size_t k = 0; k < a.nodes.size(); ++k) {
      std::vector<double> ta(a.temperature_K.cols()), tb(b.temperature_K.cols());
      for (Eigen::Index s = 0; s < a.temperature_K.cols(); ++s) ta[s] = a.temperature_K(k, s);
      for (Eigen::Index s = 0; s < b.temperature_K.cols(); ++s) tb[s] = b.temperature_K(k, s);
      ref[a.nodes[k]] = ta;
      red[a.nodes[k]] = tb;
    }
    std::vector<double> times(a.times_s.data(), a.times_s.data() + a.times_s.size());
    json data = {{"times_s", times}, {"nodes", a.nodes}, {"reference_K", ref}, {"reduced_K", red},
                 {"tolerance_K", run.tolerance_K}, {"period_s", a.transient ? a.loads.period_s : 0.0},
                 {"in_shadow", std::vector<bool>(a.loads.in_shadow.begin(), a.loads.in_shadow.end())}};
    // A merged reduction: the plot lists each merged node's members.
    for (const auto& [original, merged] : run.reduced.model.node_map) data["node_map"][original] = merged;
    plot("temperatures_before_after", std::move(data), "temperatures.png");
  }
  {
    Eigen::VectorXd dT(run.nodes.size());
    for (size_t k = 0; k < run.nodes.size(); ++k) dT[k] = run.nodes[k].max_abs_dT_K;
    char t1[96], t2[96];
    std::snprintf(t1, sizeof t1, "reference: %d faces", run.faces_before);
    std::snprintf(t2, sizeof t2, "%s: %d faces, by node", run.strategy.c_str(), run.faces_after);
    json panels = json::array({mesh_panel(run.reference_mesh, t1, nullptr, ""),
                               mesh_panel(run.reduced.model.mesh, t2, nullptr, ""),
                               mesh_panel(run.reduced.model.mesh, "max |dT| per node [K]", &dT, "max |dT| [K]")});
    plot("mesh_view", {{"panels", panels}}, "mesh.png");
  }
  for (auto& d : drawn)
    if (std::string w = d.get(); !w.empty()) warnings.push_back(std::move(w));
  return warnings;
}

std::string reduction_summary(const ReductionRun& run) {
  std::ostringstream o;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%s reduction: %d -> %d faces (%.1f %% removed); verified max |dT| %.4f K (node %s) "
                "<= tolerance %.3g K; noise floor %.4f K; %d trials in %.1f s\n",
                run.strategy.c_str(), run.faces_before, run.faces_after,
                100.0 * (1.0 - static_cast<double>(run.faces_after) / std::max(1, run.faces_before)),
                run.max_temperature_difference_K, run.max_difference_node.c_str(), run.tolerance_K,
                run.noise_floor_K, run.trials, run.seconds_total);
  o << buf;
  std::snprintf(buf, sizeof buf, "max |dT| = %.4f \u00b1 %.4f K (upper bound %.4f K at %.1f %%) over %d fresh seed pairs\n",
                run.verification.max_abs_dT_K, run.verification.standard_error_K, run.verification.upper_bound_K,
                100.0 * run.verification.confidence, run.verification.replicates);
  o << buf;
  if (run.merging) {
    const NodeMerging& m = *run.merging;
    std::snprintf(buf, sizeof buf,
                  "node merging: %d -> %d nodes (%zu merges, max |dT| %.4f K within %.4g K); decimation within %.4g K%s\n",
                  m.nodes_before, m.nodes_after, m.steps.size(), m.dT_K, m.budget_K, m.decimation_tolerance_K,
                  m.fallback.empty() ? "" : "; merged model given up");
    o << buf;
  }
  if (run.cases.size() > 1)
    for (const auto& c : run.cases) {
      std::snprintf(buf, sizeof buf, "  case %-12s verified max |dT| %.4f K (node %s, t = %.0f s); noise floor %.4f K\n",
                    c.name.c_str(), c.max_temperature_difference_K, c.max_difference_node.c_str(),
                    c.max_difference_time_s, c.noise_floor_K);
      o << buf;
    }
  for (const auto& n : run.nodes) {
    std::snprintf(buf, sizeof buf, "  %-16s %5d -> %5d faces  ratio %.2f  max|dT| %.4f K\n", n.name.c_str(),
                  n.faces_before, n.faces_after, n.ratio, n.max_abs_dT_K);
    o << buf;
    if (n.stopped_by != "none") {  // the decimator ended above the faces the ratio asked for
      std::snprintf(buf, sizeof buf, "  %-16s asked %.2f (%d faces), stopped by %s\n", "", n.requested_ratio,
                    n.target_faces, n.stopped_by.c_str());
      o << buf;
    }
  }
  return o.str();
}

}  // namespace thermodec
