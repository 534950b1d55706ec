#include "thermodec/exchange/write_csv_tables.h"
#include "thermodec/thermal/internal_power.h"

#include <ostream>

#include "number_text.h"
#include "thermodec/common/atomic_write.h"

namespace thermodec {
namespace {

using exchange_text::real;

std::string csv_field(const std::string& s) {  // RFC 4180 quoting where needed
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::vector<std::filesystem::path> write_csv_tables(const std::filesystem::path& prefix, const ExportedNetwork& e,
                                                    const std::vector<std::filesystem::path>& protected_inputs) {
  const ThermalNetwork& net = e.network;
  const int n = net.num_nodes(), S = static_cast<int>(e.times_s.size());
  const std::filesystem::path temperatures = prefix.string() + "_temperatures.csv";
  const std::filesystem::path couplings = prefix.string() + "_couplings.csv";
  const std::filesystem::path loads = prefix.string() + "_loads.csv";
  // The three tables replace an earlier export together, once all three are written.
  AtomicFileSet files;
  files.add(temperatures, [&](std::ostream& out) {
    out << "time_s";
    for (const auto& name : net.node_names) out << "," << csv_field(name);
    out << "\n";
    for (int k = 0; k < S; ++k) {
      out << real(e.times_s[k]);
      for (int i = 0; i < n; ++i) out << "," << real(e.temperature_K(i, k));
      out << "\n";
    }
  }, protected_inputs);
  files.add(couplings, [&](std::ostream& out) {
    out << "from,to,type,value,unit\n";
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (net.conductance_W_per_K(i, j) != 0.0)
          out << csv_field(net.node_names[i]) << "," << csv_field(net.node_names[j]) << ",GL," << real(net.conductance_W_per_K(i, j)) << ",W/K\n";
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j)
        if (net.radiative_couplings_m2(i, j) != 0.0)
          out << csv_field(net.node_names[i]) << "," << csv_field(net.node_names[j]) << ",GR," << real(net.radiative_couplings_m2(i, j)) << ",m^2\n";
      if (net.to_space_couplings_m2[i] != 0.0)
        out << csv_field(net.node_names[i]) << ",space,GR," << real(net.to_space_couplings_m2[i]) << ",m^2\n";
    }
  }, protected_inputs);
  const std::filesystem::path nodes = prefix.string() + "_nodes.csv";
  const bool tables = e.transient && e.table_times_s.size() > 1;
  files.add(loads, [&](std::ostream& out) {
    out << "time_s,node,solar_W,albedo_W,earth_ir_W,internal_W\n";
    const int K = tables ? static_cast<int>(e.table_times_s.size()) : S;
    // Scheduled internal power: the value over the interval ending at each time (as simulate).
    const Eigen::MatrixXd scheduled = tables && has_power_schedules(net)
                                          ? scheduled_power_W(net, e.table_times_s, e.period_s)
                                          : Eigen::MatrixXd::Zero(n, K);
    for (int k = 0; k < K; ++k)
      for (int i = 0; i < n; ++i)
        out << real(tables ? e.table_times_s[k] : e.times_s[k]) << "," << csv_field(net.node_names[i]) << ","
            << real(tables ? e.table_solar_W(i, k) : e.solar_W(i, k)) << ","
            << real(tables ? e.table_albedo_W(i, k) : e.albedo_W(i, k)) << ","
            << real(tables ? e.table_earth_ir_W(i, k) : e.earth_ir_W(i, k)) << ","
            << real(net.power_W[i] + scheduled(i, k)) << "\n";
  }, protected_inputs);
  files.add(nodes, [&](std::ostream& out) {
    for (const std::string& line : e.provenance) out << "# " << line << "\n";
    out << "node,kind,capacitance_J_per_K,internal_W,fixed_temperature_K,initial_temperature_K,area_m2,absorptivity,"
           "emissivity,period_s\n";
    for (int i = 0; i < n; ++i) {
      const bool fixed = net.is_fixed(i);
      const char* kind = fixed ? "boundary" : net.capacitance_J_per_K[i] > 0.0 ? "diffusion" : "arithmetic";
      out << csv_field(net.node_names[i]) << "," << kind << "," << real(net.capacitance_J_per_K[i]) << ","
          << real(net.power_W[i]) << "," << (fixed ? real(net.fixed_temperature_K[i]) : std::string()) << ","
          << real(fixed ? net.fixed_temperature_K[i] : e.temperature_K(i, 0)) << "," << real(e.area_m2[i]) << ","
          << real(e.absorptivity[i]) << "," << real(e.emissivity[i]) << "," << real(e.period_s) << "\n";
    }
    out << "space,boundary,0,0," << real(net.sink_temperature_K) << "," << real(net.sink_temperature_K) << ",0,0,0,"
        << real(e.period_s) << "\n";
  }, protected_inputs);
  return files.commit();
}

}  // namespace thermodec
