#include "thermodec/exchange/exported_network.h"

#include "thermodec/common/errors.h"
#include "thermodec/mesh/face_geometry.h"

namespace thermodec {

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
  e.period_s = result.transient ? result.loads.period_s : 0.0;
  e.orbits = result.orbits;
  e.times_s = result.loads.times_s;
  // Reflected solar (direct + albedo bounced off the spacecraft) is solar-band power: booked
  // with the direct sun, as ESATAN's QS and Thermal Desktop's solar loads hold it.
  e.solar_W = result.loads.solar_W + result.loads.reflected_solar_W;
  e.albedo_W = result.loads.albedo_W;
  e.earth_ir_W = result.loads.earth_ir_W;
  e.temperature_K = result.temperature_K;
  return e;
}

}  // namespace thermodec
