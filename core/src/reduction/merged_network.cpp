#include "thermodec/reduction/merged_network.h"

#include <cmath>

#include "thermodec/common/errors.h"

namespace thermodec {
namespace {

// P (merged x original) with P(m, i) = 1 when node i is a member of m: sums are P X P^T.
Eigen::MatrixXd membership(const NodeMergeMap& map) {
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(map.num_merged(), static_cast<Eigen::Index>(map.merged_of_node.size()));
  for (std::size_t i = 0; i < map.merged_of_node.size(); ++i) p(map.merged_of_node[i], static_cast<Eigen::Index>(i)) = 1.0;
  return p;
}

// (A matrix never filled, 0 x 0, stays empty.)
Eigen::MatrixXd rows_summed(const Eigen::MatrixXd& p, const Eigen::MatrixXd& x) {
  return x.rows() != p.cols() ? x : Eigen::MatrixXd(p * x);
}

// Standard errors of sums of independent terms: sqrt of the summed variances.
Eigen::MatrixXd rows_in_quadrature(const Eigen::MatrixXd& p, const Eigen::MatrixXd& se) {
  return se.rows() != p.cols() ? se : Eigen::MatrixXd((p * se.cwiseAbs2()).cwiseSqrt());
}

}  // namespace

NodeCouplings merge_couplings(const NodeCouplings& c, const NodeMergeMap& map) {
  const Eigen::Index n = static_cast<Eigen::Index>(map.merged_of_node.size());
  if (c.radiative_couplings_m2.rows() != n || c.area_m2.size() != n)
    throw InvalidInput("merge_couplings: the couplings have " + std::to_string(c.area_m2.size()) + " nodes, the map " +
                       std::to_string(n));
  const Eigen::MatrixXd p = membership(map);
  NodeCouplings m;
  m.area_m2 = p * c.area_m2;
  m.radiative_couplings_m2 = p * c.radiative_couplings_m2 * p.transpose();
  m.to_space_couplings_m2 = p * c.to_space_couplings_m2;
  // F_MN = sum_{i in M} A_i F_iN / A_M.
  const Eigen::MatrixXd af = c.area_m2.asDiagonal() * c.view_factors;
  const Eigen::VectorXd inv_area = m.area_m2.unaryExpr([](double a) { return a > 0.0 ? 1.0 / a : 0.0; });
  m.view_factors = inv_area.asDiagonal() * (p * af * p.transpose());
  m.to_space = inv_area.asDiagonal() * (p * c.area_m2.cwiseProduct(c.to_space));
  auto both_sides = [&](const Eigen::MatrixXd& se) {
    return se.rows() != p.cols() || se.cols() != p.cols() ? se
                                                          : Eigen::MatrixXd((p * se.cwiseAbs2() * p.transpose()).cwiseSqrt());
  };
  m.radiative_couplings_standard_error = both_sides(c.radiative_couplings_standard_error);
  m.to_space_couplings_standard_error = rows_in_quadrature(p, c.to_space_couplings_standard_error);
  if (c.view_factors_standard_error.rows() == n)
    m.view_factors_standard_error =
        inv_area.asDiagonal() * both_sides(Eigen::MatrixXd(c.area_m2.asDiagonal() * c.view_factors_standard_error));
  if (c.to_space_standard_error.size() == n)
    m.to_space_standard_error = inv_area.asDiagonal() *
                                rows_in_quadrature(p, Eigen::MatrixXd(c.area_m2.cwiseProduct(c.to_space_standard_error)));
  m.diagnostics = c.diagnostics;
  return m;
}

Loads merge_loads(const Loads& l, const NodeMergeMap& map) {
  const Eigen::Index n = static_cast<Eigen::Index>(map.merged_of_node.size());
  if (l.solar_W.rows() != n)
    throw InvalidInput("merge_loads: the loads have " + std::to_string(l.solar_W.rows()) + " nodes, the map " +
                       std::to_string(n));
  const Eigen::MatrixXd p = membership(map);
  Loads m = l;
  m.solar_W = rows_summed(p, l.solar_W);
  m.albedo_W = rows_summed(p, l.albedo_W);
  m.earth_ir_W = rows_summed(p, l.earth_ir_W);
  m.reflected_solar_W = rows_summed(p, l.reflected_solar_W);
  m.knot_solar_W = rows_summed(p, l.knot_solar_W);
  m.knot_albedo_W = rows_summed(p, l.knot_albedo_W);
  m.knot_earth_ir_W = rows_summed(p, l.knot_earth_ir_W);
  m.knot_reflected_solar_W = rows_summed(p, l.knot_reflected_solar_W);
  m.sampling_standard_error_W = rows_in_quadrature(p, l.sampling_standard_error_W);
  if (l.orbit_mean_standard_error_W.size() == n)
    m.orbit_mean_standard_error_W = rows_in_quadrature(p, Eigen::MatrixXd(l.orbit_mean_standard_error_W)).col(0);
  return m;
}

SimulationResult result_through_node_map(const SimulationResult& merged,
                                         const std::vector<std::pair<std::string, std::string>>& node_map) {
  const std::vector<int> idx = merged_index_of_original(node_map, merged.nodes);
  SimulationResult r = merged;
  r.loads = Loads{};
  r.internal_power_W.resize(0);
  r.nodes.clear();
  r.temperature_K.resize(static_cast<Eigen::Index>(idx.size()), merged.temperature_K.cols());
  const bool noise = merged.noise_K.size() == static_cast<Eigen::Index>(merged.nodes.size());
  r.noise_K.resize(noise ? static_cast<Eigen::Index>(idx.size()) : 0);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    r.nodes.push_back(node_map[k].first);
    r.temperature_K.row(static_cast<Eigen::Index>(k)) = merged.temperature_K.row(idx[k]);
    if (noise) r.noise_K[static_cast<Eigen::Index>(k)] = merged.noise_K[idx[k]];
  }
  return r;
}

}  // namespace thermodec
