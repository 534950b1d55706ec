#include "thermodec/thermal/network.h"

#include <cmath>
#include <limits>
#include <string>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec {

ThermalNetwork thermal_network(const ThermalModel& model, const NodeCouplings& couplings) {
  const int n = static_cast<int>(model.nodes.size());
  if (couplings.radiative_couplings_m2.rows() != n || couplings.radiative_couplings_m2.cols() != n ||
      couplings.to_space_couplings_m2.size() != n)
    throw InvalidInput("radiative couplings are for " + std::to_string(couplings.radiative_couplings_m2.rows()) +
                       " nodes, the model has " + std::to_string(n));
  ThermalNetwork net;
  net.capacitance_J_per_K.resize(n);
  net.power_W.resize(n);
  net.fixed_temperature_K.resize(n);
  for (int i = 0; i < n; ++i) {
    const Node& node = model.nodes[i];
    net.node_names.push_back(node.name);
    net.capacitance_J_per_K[i] = node.capacitance_J_per_K;
    net.power_W[i] = node.power_schedule_W.empty() ? node.power_W : 0.0;
    net.power_schedule_W.push_back(node.power_schedule_W);
    if (node.heater) net.heaters.push_back({i, *node.heater});
    net.fixed_temperature_K[i] = node.fixed_temperature_K ? *node.fixed_temperature_K
                                                          : std::numeric_limits<double>::quiet_NaN();
  }
  net.conductance_W_per_K = Eigen::MatrixXd::Zero(n, n);
  for (size_t k = 0; k < model.conductances.size(); ++k) {
    const Conductance& c = model.conductances[k];
    if (c.from < 0 || c.from >= n || c.to < 0 || c.to >= n)
      throw InvalidInput("conductance " + std::to_string(k) + " links an unknown node");
    if (!(c.conductance_W_per_K >= 0.0))
      throw InvalidInput("conductance " + std::to_string(k) + " (" + model.nodes[c.from].name + " - " +
                         model.nodes[c.to].name + ") must be >= 0 W/K");
    if (c.from == c.to) continue;  // a link of a node to itself carries no heat
    net.conductance_W_per_K(c.from, c.to) += c.conductance_W_per_K;
    net.conductance_W_per_K(c.to, c.from) += c.conductance_W_per_K;
  }
  const Eigen::MatrixXd& gr = couplings.radiative_couplings_m2;
  net.radiative_couplings_m2 = 0.5 * (gr + gr.transpose());
  net.to_space_couplings_m2 = couplings.to_space_couplings_m2;
  net.sink_temperature_K = kDeepSpaceTemperature_K;
  validate_network(net);
  return net;
}

void validate_network(const ThermalNetwork& net) {
  const int n = net.num_nodes();
  if (static_cast<int>(net.node_names.size()) != n || net.power_W.size() != n ||
      net.fixed_temperature_K.size() != n || net.conductance_W_per_K.rows() != n ||
      net.conductance_W_per_K.cols() != n || net.radiative_couplings_m2.rows() != n ||
      net.radiative_couplings_m2.cols() != n || net.to_space_couplings_m2.size() != n)
    throw InvalidInput("thermal network: inconsistent sizes for " + std::to_string(n) + " nodes");
  for (int i = 0; i < n; ++i) {
    const std::string& name = net.node_names[i];
    if (!(net.capacitance_J_per_K[i] >= 0.0) || !std::isfinite(net.capacitance_J_per_K[i]))
      throw InvalidInput("node '" + name + "': capacitance must be finite and >= 0 J/K");
    if (!std::isfinite(net.power_W[i])) throw InvalidInput("node '" + name + "': power is not finite");
    if (net.is_fixed(i) && !(net.fixed_temperature_K[i] > 0.0 && std::isfinite(net.fixed_temperature_K[i])))
      throw InvalidInput("node '" + name + "': fixed temperature must be > 0 K");
    if (!net.power_schedule_W.empty())
      for (const auto& [t, w] : net.power_schedule_W[i])
        if (!std::isfinite(t) || !std::isfinite(w)) throw InvalidInput("node '" + name + "': power schedule is not finite");
    if (!(net.to_space_couplings_m2[i] >= 0.0))
      throw InvalidInput("node '" + name + "': radiative coupling to space must be >= 0 m^2");
  }
  if (!net.power_schedule_W.empty() && static_cast<int>(net.power_schedule_W.size()) != n)
    throw InvalidInput("thermal network: power schedules for " + std::to_string(net.power_schedule_W.size()) + " of " +
                       std::to_string(n) + " nodes");
  for (const NetworkHeater& h : net.heaters) {
    if (h.node < 0 || h.node >= n) throw InvalidInput("thermal network: a heater names a node out of range");
    const Thermostat& t = h.thermostat;
    if (net.is_fixed(h.node) || !(net.capacitance_J_per_K[h.node] > 0.0))
      throw InvalidInput("node '" + net.node_names[h.node] + "': a thermostat needs a free node with a capacitance > 0 J/K");
    if (!(t.on_K > 0.0 && t.on_K < t.off_K && std::isfinite(t.off_K) && t.power_W > 0.0 && std::isfinite(t.power_W)))
      throw InvalidInput("node '" + net.node_names[h.node] + "': heater needs 0 < on_K < off_K and power_W > 0");
  }
  if (!net.conductance_W_per_K.allFinite() || (net.conductance_W_per_K.array() < 0.0).any())
    throw InvalidInput("thermal network: conductances must be finite and >= 0 W/K");
  if (!net.radiative_couplings_m2.allFinite())
    throw InvalidInput("thermal network: radiative couplings are not finite");
  if (!(net.sink_temperature_K >= 0.0)) throw InvalidInput("thermal network: sink temperature must be >= 0 K");
}

}  // namespace thermodec
