#include "thermodec/thermal/simulate.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "thermodec/common/errors.h"
#include "thermodec/thermal/internal_power.h"
#include "thermodec/thermal/orbit_transient.h"
#include "thermodec/thermal/temperature_noise.h"

namespace thermodec {

SimulationResult simulate(const ThermalModel& model, const NodeCouplings& couplings, const Loads& loads,
                          const SimulationSettings& settings) {
  ThermalNetwork net = thermal_network(model, couplings);
  const int n = net.num_nodes();
  const Eigen::MatrixXd total = loads.total_W();
  const int S = loads.num_steps();
  if (S < 1 || total.rows() != n || total.cols() != S)
    throw InvalidInput("simulate: loads are " + std::to_string(total.rows()) + " x " + std::to_string(total.cols()) +
                       " for " + std::to_string(n) + " nodes and " + std::to_string(S) + " times");

  SimulationResult r;
  r.nodes = net.node_names;
  r.loads = loads;
  r.internal_power_W = net.power_W;
  const bool orbit = loads.period_s > 0.0 && S >= 2;
  const bool schedules = has_power_schedules(net);
  if (schedules && !orbit) throw InvalidInput("simulate: power_schedule_W needs an orbit (a period)");
  if (schedules) r.internal_power_W += scheduled_power_mean_W(net, loads.period_s);
  if (model.analysis.type == AnalysisType::transient_orbit && orbit) {
    TransientSettings ts = settings.transient;
    if (ts.max_orbits < 1) ts.max_orbits = model.analysis.orbits;
    OrbitTimeSettings time = settings.time;
    if (!(time.time_tolerance_K > 0.0)) time.time_tolerance_K = model.analysis.time_tolerance_K;
    const Eigen::VectorXd switches = model.environment.type == EnvironmentType::orbit
                                         ? eclipse_switch_times_s(model.environment, loads.period_s)
                                         : Eigen::VectorXd();
    const OrbitTransient ot = orbit_transient(net, loads, switches, time, ts);
    if (settings.orbit_sampling_error && S % 2 == 0 && S >= 4) {
      // Richardson on the positions: the same solve from every other position.
      TransientSettings quiet = ts;
      quiet.on_orbit = nullptr;
      const OrbitTransient half = orbit_transient(net, every_other_position(loads), switches, time, quiet);
      double d = 0.0;
      for (int k = 0; k < S / 2; ++k)
        d = std::max(d, (ot.transient.temperature_K.col(2 * k) - half.transient.temperature_K.col(k)).cwiseAbs().maxCoeff());
      r.orbit_sampling_error_K = d / 3.0;
    }
    const PeriodicTransient& tr = ot.transient;
    r.time_error_K = ot.time_error_K;
    r.solver_steps_per_orbit = ot.solver_steps_per_orbit;
    r.transient = true;
    r.times_s = tr.times_s;
    r.temperature_K = tr.temperature_K;
    r.orbits = tr.orbits;
    r.periodicity_residual_K = tr.periodicity_residual_K;
    r.energy = tr.energy;
    r.heater_power_W = ot.heater_mean_W;
  } else {
    if (!net.heaters.empty())
      throw InvalidInput("simulate: node '" + net.node_names[net.heaters[0].node] +
                         "' has a thermostat heater, which needs analysis.type transient_orbit (a steady state has no on/off cycle)");
    // The orbit mean of the schedules: exact for the steady state of the mean loads.
    if (schedules) {
      net.power_W = r.internal_power_W;
      net.power_schedule_W.clear();
    }
    // Steady: the time-averaged loads (a fixed sun has one time step, so this is exact there). An
    // orbit's mean integrates the loads as the transient applies them, with the exact eclipse
    // fraction, not the share of positions that happen to be in shadow.
    const Eigen::VectorXd switches = orbit && model.environment.type == EnvironmentType::orbit
                                         ? eclipse_switch_times_s(model.environment, loads.period_s)
                                         : Eigen::VectorXd();
    auto mean_of = [&](const Loads& l) -> Eigen::VectorXd {
      return orbit ? Eigen::VectorXd(orbit_mean_loads(l, switches).total_W().col(0)) : Eigen::VectorXd(l.total_W().rowwise().mean());
    };
    const SteadyState ss = steady_state(net, mean_of(loads), settings.newton);
    r.times_s = Eigen::VectorXd::Zero(1);
    r.temperature_K = ss.temperature_K;
    if (settings.orbit_sampling_error && orbit && S % 2 == 0 && S >= 4)
      r.orbit_sampling_error_K =
          (ss.temperature_K - steady_state(net, mean_of(every_other_position(loads)), settings.newton).temperature_K)
              .cwiseAbs()
              .maxCoeff() /
          3.0;
    if (S > 1) {  // report the loads that were applied: their orbit average
      auto avg = [](const Eigen::MatrixXd& m) { return Eigen::MatrixXd(m.rowwise().mean()); };
      Loads mean;
      if (orbit) mean = orbit_mean_loads(loads, switches);
      for (const LoadComponent& c : load_components()) r.loads.*c.W = orbit ? mean.*c.W : avg(loads.*c.W);
      r.loads.times_s = r.times_s;
      r.loads.in_shadow.assign(1, 0);
      r.loads.knot_times_s.resize(0);
      if (loads.orbit_mean_standard_error_W.size() == n) r.loads.sampling_standard_error_W = loads.orbit_mean_standard_error_W;
      else if (loads.sampling_standard_error_W.cols() == S) r.loads.sampling_standard_error_W = loads.sampling_standard_error_W.rowwise().mean();
    }
  }
  // Sampling noise per node: the couplings' and the loads' standard errors through the network.
  if (couplings.radiative_couplings_standard_error.rows() == n &&
      couplings.to_space_couplings_standard_error.size() == n) {
    const Eigen::MatrixXd& se = r.loads.sampling_standard_error_W;
    r.noise_K = temperature_noise_K(net, couplings, r.temperature_K,
                                    se.rows() == n && se.cols() == r.temperature_K.cols() ? se : Eigen::MatrixXd());
  }
  return r;
}

TemperatureDifference compare_results(const SimulationResult& a, const SimulationResult& b) {
  std::map<std::string, int> index_b;
  for (size_t i = 0; i < b.nodes.size(); ++i) index_b[b.nodes[i]] = static_cast<int>(i);
  for (const auto& name : b.nodes)
    if (std::find(a.nodes.begin(), a.nodes.end(), name) == a.nodes.end())
      throw InvalidInput("compare: node '" + name + "' is only in the second result");
  if (a.times_s.size() != b.times_s.size())
    throw InvalidInput("compare: results have " + std::to_string(a.times_s.size()) + " and " +
                       std::to_string(b.times_s.size()) + " times");
  for (int k = 0; k < a.times_s.size(); ++k)
    if (std::abs(a.times_s[k] - b.times_s[k]) > 1e-6 * std::max(1.0, std::abs(a.times_s[k])))
      throw InvalidInput("compare: time " + std::to_string(k) + " differs (" + std::to_string(a.times_s[k]) +
                         " s vs " + std::to_string(b.times_s[k]) + " s)");
  TemperatureDifference d;
  d.max_abs_K = -1.0;
  d.per_node.reserve(a.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    const auto it = index_b.find(a.nodes[i]);
    if (it == index_b.end()) throw InvalidInput("compare: node '" + a.nodes[i] + "' is only in the first result");
    TemperatureDifference::PerNode node{a.nodes[i], -1.0, 0.0};
    for (int k = 0; k < a.times_s.size(); ++k) {
      const double diff = std::abs(a.temperature_K(i, k) - b.temperature_K(it->second, k));
      if (diff > node.max_abs_K || std::isnan(diff)) node.max_abs_K = diff, node.time_s = a.times_s[k];
      if (diff > d.max_abs_K || std::isnan(diff)) {
        d.max_abs_K = diff, d.node = a.nodes[i], d.time_s = a.times_s[k], d.time_index = k;
        if (std::isnan(diff)) {
          d.per_node.push_back(node);
          return d;
        }
      }
    }
    node.max_abs_K = std::max(node.max_abs_K, 0.0);
    d.per_node.push_back(node);
  }
  if (d.max_abs_K < 0.0) d.max_abs_K = 0.0;
  return d;
}

}  // namespace thermodec
