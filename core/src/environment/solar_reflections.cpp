// Solar-band diffuse reflections between the spacecraft's own faces.
//
// Computes the power [W] each node finally absorbs of the solar-band power (direct + albedo)
// the faces reflect: a side receiving Q_s reflects (1 - alpha_s) Q_s diffusely, and node g
// absorbs the fraction B(s, g) of it, the solar-band Gebhart factors (radiation/
// gebhart_factors.h with the absorptivities) over the radiative engine's side-to-side view
// factors with reciprocity enforced (radiation/reciprocal_view_factors.h: each exchange area
// A_s F_st estimated from the rays of both sides, weighted by ray density). B depends on
// geometry only: solved once per model, a trial warm-starts from the reference's. Accuracy:
// that of the view factors (Monte Carlo, radiation/) and of the solve's tolerance; Earth-IR
// reflections between faces are neglected (docs/thermal.md).
#include <string>
#include <unordered_map>

#include "thermodec/common/errors.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/reciprocal_view_factors.h"

namespace thermodec {

void add_solar_reflections(Loads& loads, const ThermalModel& model, const SurfaceSides& sides,
                           const FaceViewFactors& view_factors, const Eigen::MatrixXd& solar_incident_W,
                           const LoadSamples* warm, LoadSamples* samples) {
  const int ns = sides.size(), num_nodes = static_cast<int>(model.nodes.size());
  if (view_factors.sides.size() != ns)
    throw InvalidInput("solar reflections: view factors are for " + std::to_string(view_factors.sides.size()) +
                       " sides, the model has " + std::to_string(ns));
  // The incident power may also hold the eclipse edges' columns (after the positions').
  const Eigen::Index S = loads.reflected_solar_W.cols();
  const Eigen::Index E = loads.has_knots() && solar_incident_W.cols() == S + loads.knot_times_s.size()
                             ? loads.knot_times_s.size() : 0;
  if (solar_incident_W.rows() != ns || loads.reflected_solar_W.rows() != num_nodes ||
      S + E != solar_incident_W.cols())
    throw InvalidInput("solar reflections: incident power is " + std::to_string(solar_incident_W.rows()) + " x " +
                       std::to_string(solar_incident_W.cols()) + " for " + std::to_string(ns) + " sides and loads of " +
                       std::to_string(loads.reflected_solar_W.cols()) + " steps");
  const Eigen::VectorXd alpha = side_absorptivity(model, sides);
  // A trial starts from the reference's solution (sides present in both; the others from 0).
  RowMatrixXd guess;
  const bool warm_ok = warm && warm->solar_gebhart.rows() == static_cast<Eigen::Index>(warm->key.size()) &&
                       warm->solar_gebhart.cols() == num_nodes + 2;
  if (warm_ok) {
    std::unordered_map<std::uint64_t, int> index;
    for (size_t i = 0; i < warm->key.size(); ++i) index.emplace(warm->key[i], static_cast<int>(i));
    guess = RowMatrixXd::Zero(ns, num_nodes + 2);
    for (int s = 0; s < ns; ++s) {
      const auto it = index.find(sides.key[s]);
      if (it != index.end()) guess.row(s) = warm->solar_gebhart.row(it->second);
    }
  }
  // note: the IR couplings enforce reciprocity per node pair themselves (radiative_couplings.h),
  // with variances; the reflections take it per side pair, before the solve.
  const FaceViewFactors reciprocal = reciprocal_view_factors(view_factors);
  const GebhartFactors solar =
      gebhart_factors(reciprocal, alpha, node_groups(sides, num_nodes), num_nodes + 1, {}, warm_ok ? &guess : nullptr);
  if (samples) samples->solar_gebhart = solar.B;
  // reflected(g, k) = sum over s, in increasing order, of (1 - alpha_s) B(s, g) incident(s, k):
  // on row-major copies, so that a side's powers and a node's sums are contiguous over the
  // steps (the column-major rows strode through memory: ~6 % of a Juno trial). The same
  // products and sums in the same order, so the same bits.
  const Eigen::Index T = S + E;
  const RowMatrixXd incident = solar_incident_W;
  RowMatrixXd reflected_rows = RowMatrixXd::Zero(num_nodes, T);
  for (int s = 0; s < ns; ++s) {
    if (solar_incident_W.row(s).isZero()) continue;
    const double* in = incident.data() + s * T;
    for (int g = 0; g < num_nodes; ++g) {
      const double b = solar.B(s, g);
      if (b == 0.0) continue;
      const double w = (1.0 - alpha[s]) * b;
      double* out = reflected_rows.data() + g * T;
      for (Eigen::Index k = 0; k < T; ++k) out[k] += w * in[k];
    }
  }
  const Eigen::MatrixXd reflected = reflected_rows;
  loads.reflected_solar_W += reflected.leftCols(S);
  if (E > 0) loads.knot_reflected_solar_W += reflected.rightCols(E);
}

}  // namespace thermodec
