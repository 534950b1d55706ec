#include "thermodec/exchange/exported_network.h"

#include "thermodec/common/errors.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/thermal/internal_power.h"
#include "thermodec/thermal/orbit_transient.h"

#include <algorithm>
#include <vector>

namespace thermodec {

std::vector<std::pair<double, double>> schedule_doublets(const std::vector<std::pair<double, double>>& s, double P) {
  std::vector<std::pair<double, double>> out;
  const double ramp = ExportedNetwork::kSwitchRamp_s;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double end = k + 1 < s.size() ? s[k + 1].first : P;
    out.emplace_back(s[k].first, s[k].second);
    if (end - ramp > s[k].first) out.emplace_back(end - ramp, s[k].second);
  }
  if (!s.empty()) out.emplace_back(P, s.front().second);
  return out;
}

ExportedNetwork exported_network(const ThermalModel& model, const NodeCouplings& couplings,
                                 const SimulationResult& result, const std::string& title) {
  ExportedNetwork e;
  e.title = title;
  e.network = thermal_network(model, couplings);
  const int n = e.network.num_nodes();
  if (result.temperature_K.rows() != n || result.loads.solar_W.rows() != n)
    throw InvalidInput("export: the simulation result has " + std::to_string(result.temperature_K.rows()) +
                       " nodes, the model " + std::to_string(n));
  // Thermo-optical properties per node, weighted by the area of each radiating side: what a
  // lumped-node tool shows as the node's A, ALP and EPS (the couplings already hold the exact,
  // per-face emissivities).
  e.area_m2 = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd alpha_area = Eigen::VectorXd::Zero(n), eps_area = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd area = face_areas(model.mesh.V, model.mesh.F);
  for (int f = 0; f < model.mesh.num_faces(); ++f) {
    const int node = model.mesh.face_node[f];
    if (node < 0) continue;
    for (int side = 0; side < 2; ++side) {
      const int m = side == 0 ? model.mesh.face_material[f] : (model.mesh.is_two_sided(f) ? model.mesh.face_back_material[f] : -1);
      if (m < 0) continue;
      e.area_m2[node] += area[f];
      alpha_area[node] += area[f] * model.materials[m].absorptivity;
      eps_area[node] += area[f] * model.materials[m].emissivity;
    }
  }
  e.absorptivity = alpha_area.cwiseQuotient(e.area_m2.cwiseMax(1e-300));
  e.emissivity = eps_area.cwiseQuotient(e.area_m2.cwiseMax(1e-300));
  e.transient = result.transient;
  if (!result.transient && has_power_schedules(e.network) && result.internal_power_W.size() == n) {
    e.network.power_W = result.internal_power_W;  // the orbit mean the steady state solved
    e.network.power_schedule_W.assign(static_cast<std::size_t>(n), {});
  }
  e.period_s = result.transient ? result.loads.period_s : 0.0;
  e.orbits = result.orbits;
  e.times_s = result.loads.times_s;
  // Reflected solar (direct + albedo bounced off the spacecraft) is solar-band power: booked
  // with the direct sun, as ESATAN's QS and Thermal Desktop's solar loads hold it.
  e.solar_W = result.loads.solar_W + result.loads.reflected_solar_W;
  e.albedo_W = result.loads.albedo_W;
  e.earth_ir_W = result.loads.earth_ir_W;
  e.temperature_K = result.temperature_K;
  e.table_times_s = e.times_s;
  e.table_solar_W = e.solar_W;
  e.table_albedo_W = e.albedo_W;
  e.table_earth_ir_W = e.earth_ir_W;
  if (e.transient && model.environment.type == EnvironmentType::orbit && e.times_s.size() >= 2) {
    // The loads exactly as the transient applies them: positions plus both sides of each switch.
    const Eigen::VectorXd switches = eclipse_switch_times_s(model.environment, e.period_s);
    std::vector<double> t(e.times_s.data(), e.times_s.data() + e.times_s.size());
    const double ramp = ExportedNetwork::kSwitchRamp_s;
    for (Eigen::Index i = 0; i < switches.size(); ++i) {
      t.push_back(switches[i]);
      if (switches[i] + ramp < e.period_s) t.push_back(switches[i] + ramp);
    }
    // The other sunlit knots (environment/loads.h): the interpolation has a corner at each.
    for (Eigen::Index i = 0; i < result.loads.knot_times_s.size(); ++i) t.push_back(result.loads.knot_times_s[i]);
    std::sort(t.begin(), t.end());
    // A position within the ramp of a switch would break the order the tools need.
    std::vector<double> kept;
    for (const double x : t)
      if (kept.empty() || x - kept.back() >= 0.5 * ramp) kept.push_back(x);
    const Eigen::Map<const Eigen::VectorXd> times(kept.data(), static_cast<Eigen::Index>(kept.size()));
    const Loads at = loads_at(result.loads, times, switches);
    e.table_times_s = times;
    e.table_solar_W = at.solar_W + at.reflected_solar_W;
    e.table_albedo_W = at.albedo_W;
    e.table_earth_ir_W = at.earth_ir_W;
  }
  if (model.certificate) e.provenance = certificate_lines(*model.certificate);
  return e;
}

}  // namespace thermodec
