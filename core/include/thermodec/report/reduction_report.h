#pragma once
//! Outputs of `thermodec reduce`: the reduced model (mesh + model.json loadable by every
//! command), report.json for machines, PNG plots and a short summary for people.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "thermodec/reduction/reduce_model.h"

namespace thermodec {

//! report.json content: strategy, tolerance_K, faces_before, faces_after,
//! max_temperature_difference_K (+ node and time), noise_floor_K, nodes{name: {faces_before,
//! faces_after, ratio, requested_ratio, predicted_ratio, max_abs_dT_K, area_before_m2,
//! area_after_m2, target_faces, faces_removed, stopped_by, blocked_edges{reason: edges}}},
//! sensitivity curves, predicted-vs-real points, search history, timings.
nlohmann::json reduction_report_json(const ReductionRun& run);

//! report.json's "node_merging" (reduce --merge-nodes): nodes_before, nodes_after, kept,
//! candidates, trials, budget_K, dT_K, decimation_tolerance_K, traced_dT_K, traced_simulations, merges [{merged, with (original
//! nodes of the two), pair_dT_K, dT_K, nodes_after, faces (of the merged node)}], node_map {original: merged}, seconds,
//! fallback (only when the merged model was given up).
nlohmann::json node_merging_json(const NodeMerging& merging);

//! Files written into `out_dir` (atomically; `protected_inputs` are never overwritten; the
//! first of them is the input model, recorded as report.json's `input_model`):
//! model.json + reduced.obj, report.json, sensitivity.png (informed), predicted_vs_real.png
//! (informed), temperatures.png, mesh.png. A failed plot is reported in the returned
//! warnings; the model and report are always written first.
//! \return warnings (empty when every plot succeeded).
std::vector<std::string> write_reduction_outputs(const ReductionRun& run, const std::filesystem::path& out_dir,
                                                 const std::vector<std::filesystem::path>& protected_inputs,
                                                 bool plots = true);

//! A few lines for stdout: faces before/after, verified max |dT|, noise floor, time, and one
//! line per node.
std::string reduction_summary(const ReductionRun& run);

}  // namespace thermodec
