#include "thermodec/reduction/sensitivity.h"

#include <atomic>
#include <cmath>
#include <numeric>
#include <tbb/parallel_for.h>

#include "thermodec/common/errors.h"

namespace thermodec {

std::vector<SensitivityCurve> sensitivity_analysis(int num_nodes, const TrialFunction& trial,
                                                   const SensitivityOptions& options,
                                                   const std::vector<int>& nodes_in) {
  if (num_nodes < 1) throw InvalidInput("sensitivity analysis needs at least one node");
  if (!(options.cap_K > 0)) throw InvalidInput("sensitivity cap must be > 0 K");
  if (options.ratios.empty()) throw InvalidInput("sensitivity analysis needs at least one ratio");
  std::vector<double> all_ratios = options.ratios;
  all_ratios.insert(all_ratios.end(), options.ratios_beyond.begin(), options.ratios_beyond.end());
  for (size_t i = 0; i < all_ratios.size(); ++i) {
    const double r = all_ratios[i];
    if (!(r > 0 && r < 1) || (i > 0 && !(r > all_ratios[i - 1])))
      throw InvalidInput("sensitivity ratios must increase strictly within (0, 1)");
  }
  const bool beyond = !options.ratios_beyond.empty() && !options.node_faces_before.empty();
  if (beyond && options.node_faces_before.size() != static_cast<size_t>(num_nodes))
    throw InvalidInput("sensitivity: node_faces_before needs one count per node");
  std::vector<int> nodes = nodes_in;
  if (nodes.empty()) {
    nodes.resize(num_nodes);
    std::iota(nodes.begin(), nodes.end(), 0);
  }
  for (int n : nodes)
    if (n < 0 || n >= num_nodes) throw InvalidInput("sensitivity node index out of range: " + std::to_string(n));

  std::vector<SensitivityCurve> curves(nodes.size());
  std::atomic<int> done{0};
  // note: sweeps of different nodes are independent given the reference; within one node the
  // sweep is sequential because it stops at the cap.
  auto sweep = [&](size_t i) {
    SensitivityCurve& c = curves[i];
    c.node = nodes[i];
    auto run = [&](double r) {
      Eigen::VectorXd ratios = Eigen::VectorXd::Zero(num_nodes);
      ratios[c.node] = r;
      return trial(ratios);
    };
    auto faces_of = [&](const TrialResult& res) {
      return res.node_faces_after.size() > c.node ? res.node_faces_after[c.node] : -1;
    };
    // Too sensitive at the first ratio: halve it until a trial is within the threshold; those
    // points go in front of the curve, in increasing order.
    const TrialResult at_first = run(options.ratios.front());
    double below = options.ratios.front();
    for (int h = 0; h < options.halvings_below_first && !(at_first.max_abs_dT_K <= options.refine_first_above_K); ++h) {
      below *= 0.5;
      const TrialResult res = run(below);
      c.ratios.insert(c.ratios.begin(), below);
      c.max_abs_dT_K.insert(c.max_abs_dT_K.begin(), res.max_abs_dT_K);
      c.faces_after.insert(c.faces_after.begin(), faces_of(res));
      c.dT_K.insert(c.dT_K.begin(), res.dT_K);
      if (res.max_abs_dT_K <= options.refine_first_above_K) break;
    }
    int last_faces = -1;
    // A sample that reached its face count (the decimator was not the limit) lets the sweep
    // go on past the grid's end. Within one face of it counts: an edge collapse removes two
    // faces, so whole collapses cannot always meet the count (NPP_16's node_053: 24 of 328
    // faces at 0.93, which asks 23).
    auto reached = [&](double r, int faces) {
      return faces >= 0 && faces <= std::lround(options.node_faces_before[c.node] * (1.0 - r)) + 1;
    };
    const std::size_t grid = options.ratios.size(), last = beyond ? all_ratios.size() : grid;
    for (std::size_t k = 0; k < last; ++k) {
      const double r = all_ratios[k];
      if (k >= grid && !reached(all_ratios[k - 1], c.faces_after.back())) break;
      const TrialResult res = k == 0 ? at_first : run(r);
      const int faces = faces_of(res);
      if (faces >= 0 && faces == last_faces) {  // the decimator cannot go further alone
        c.stalled_ratio = r;
        break;
      }
      c.ratios.push_back(r);
      c.max_abs_dT_K.push_back(res.max_abs_dT_K);
      c.faces_after.push_back(faces);
      c.dT_K.push_back(res.dT_K);
      last_faces = faces;
      if (!(res.max_abs_dT_K <= options.cap_K)) break;
    }
    const int d = ++done;
    if (options.progress) options.progress(d, static_cast<int>(nodes.size()));
  };
  if (options.parallel) {
    tbb::parallel_for(size_t(0), nodes.size(), sweep);
  } else {
    for (size_t i = 0; i < nodes.size(); ++i) sweep(i);
  }
  return curves;
}

}  // namespace thermodec
