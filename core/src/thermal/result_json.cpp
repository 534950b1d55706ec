#include "thermodec/thermal/result_json.h"

#include <fstream>

#include "thermodec/common/errors.h"
#include "thermodec/common/version.h"

namespace thermodec {
namespace {
std::vector<double> row(const Eigen::MatrixXd& m, int i) {
  std::vector<double> v(m.cols());
  for (int k = 0; k < m.cols(); ++k) v[k] = m(i, k);
  return v;
}
}  // namespace

nlohmann::json result_to_json(const SimulationResult& r) {
  using nlohmann::json;
  json j;
  j["schema_version"] = kResultSchemaVersion;
  j["thermodec_version"] = kThermodecVersion;
  j["nodes"] = r.nodes;
  j["times_s"] = std::vector<double>(r.times_s.data(), r.times_s.data() + r.times_s.size());
  j["analysis"] = r.transient ? "transient_orbit" : "steady";
  j["period_s"] = r.transient ? r.loads.period_s : 0.0;
  json temps = json::object(), loads = json::object(), summary = json::object();
  const Eigen::MatrixXd total = r.loads.total_W();
  for (size_t i = 0; i < r.nodes.size(); ++i) {
    const int n = static_cast<int>(i);
    temps[r.nodes[i]] = row(r.temperature_K, n);
    json l;
    for (const LoadComponent& c : load_components()) l[c.name] = row(r.loads.*c.W, n);
    l["internal"] = r.internal_power_W.size() > n ? r.internal_power_W[n] : 0.0;
    if (r.heater_power_W.size() > n) l["heater"] = r.heater_power_W[n];  // orbit mean [W]
    l["total_external"] = row(total, n);
    loads[r.nodes[i]] = l;
    summary[r.nodes[i]] = {{"min_K", r.temperature_K.row(n).minCoeff()},
                           {"mean_K", r.temperature_K.row(n).mean()},
                           {"max_K", r.temperature_K.row(n).maxCoeff()}};
    if (r.noise_K.size() == static_cast<Eigen::Index>(r.nodes.size())) summary[r.nodes[i]]["noise_K"] = r.noise_K[n];
  }
  j["temperatures_K"] = temps;
  j["loads_W"] = loads;
  // The estimated time-discretization error beside the per-node figures (max over nodes/times).
  if (r.transient) summary["time_error_K"] = r.time_error_K;
  // ... and that of sampling the loads at S orbit positions (0 for a fixed sun).
  if (r.loads.period_s > 0.0) summary["orbit_sampling_error_K"] = r.orbit_sampling_error_K;
  j["summary"] = summary;
  j["in_shadow"] = std::vector<bool>(r.loads.in_shadow.begin(), r.loads.in_shadow.end());
  if (r.transient)
    j["solver"] = {{"orbits", r.orbits},
                   {"time_error_K", r.time_error_K},
                   {"solver_steps_per_orbit", r.solver_steps_per_orbit},
                   {"periodicity_residual_K", r.periodicity_residual_K},
                   {"energy_last_orbit_J",
                    {{"absorbed", r.energy.absorbed_J},
                     {"emitted_to_space", r.energy.emitted_J},
                     {"to_fixed_nodes", r.energy.to_boundary_J},
                     {"stored", r.energy.stored_J},
                     {"relative_imbalance", r.energy.relative_imbalance()}}}};
  return j;
}

SimulationResult result_from_json(const nlohmann::json& j) {
  SimulationResult r;
  try {
    r.nodes = j.at("nodes").get<std::vector<std::string>>();
    const auto times = j.at("times_s").get<std::vector<double>>();
    r.times_s = Eigen::Map<const Eigen::VectorXd>(times.data(), times.size());
    const auto& temps = j.at("temperatures_K");
    r.temperature_K.resize(r.nodes.size(), times.size());
    for (size_t i = 0; i < r.nodes.size(); ++i) {
      if (!temps.contains(r.nodes[i]))
        throw InvalidInput("temperatures_K has no entry for node '" + r.nodes[i] + "'");
      const auto t = temps.at(r.nodes[i]).get<std::vector<double>>();
      if (t.size() != times.size())
        throw InvalidInput("temperatures_K['" + r.nodes[i] + "'] has " + std::to_string(t.size()) +
                           " values for " + std::to_string(times.size()) + " times");
      for (size_t k = 0; k < t.size(); ++k) r.temperature_K(i, k) = t[k];
    }
    r.transient = j.value("analysis", "steady") == std::string("transient_orbit");
    // Optional: each node's sampling noise (results written before it was reported have none).
    if (j.contains("summary") && j["summary"].is_object()) {
      const auto& sm = j["summary"];
      Eigen::VectorXd noise(r.nodes.size());
      bool all = !r.nodes.empty();
      for (size_t i = 0; i < r.nodes.size() && all; ++i) {
        const bool has = sm.contains(r.nodes[i]) && sm[r.nodes[i]].is_object() && sm[r.nodes[i]].contains("noise_K") &&
                         sm[r.nodes[i]]["noise_K"].is_number();
        if (has) noise[i] = sm[r.nodes[i]]["noise_K"].get<double>();
        all = has;
      }
      if (all) r.noise_K = noise;
    }
  } catch (const nlohmann::json::exception& e) {
    // Name the missing key in words, not the library's code (out_of_range.403 ...).
    for (const char* key : {"nodes", "times_s", "temperatures_K"})
      if (!j.is_object() || !j.contains(key))
        throw InvalidInput(std::string("not a simulation result (thermodec simulate --json): no '") + key + "' key");
    std::string what = e.what();
    const auto end = what.find("] ");
    if (what.rfind("[json.exception.", 0) == 0 && end != std::string::npos) what = what.substr(end + 2);
    throw InvalidInput("malformed simulation result: " + what);
  }
  return r;
}

SimulationResult read_result(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw IOError("cannot read " + path.string());
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(path.string() + ": not JSON: " + e.what());
  }
  try {
    return result_from_json(j);
  } catch (const InvalidInput& e) {
    throw InvalidInput(path.string() + ": " + e.what());
  }
}

}  // namespace thermodec
