// SINDA/FLUINT input writer in the block layout Thermal Desktop generates: HEADER blocks with
// comma-separated data lines, comment lines "C" in column 1, "$" starting an end-of-line comment
// (the node's name), boundary and arithmetic nodes with a capacitance of -1.0 as Thermal Desktop
// writes them; control constants by the names of the SINDA/FLUINT manual (OUTPUT: the output
// interval of a transient).
#include "thermodec/exchange/write_sinda_network.h"

#include <algorithm>
#include <ostream>

#include "number_text.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/thermal/internal_power.h"

namespace thermodec {
namespace {

std::string real(double x) { return exchange_text::fortran_real(x); }
constexpr int kSpaceNode = 99999;
constexpr int kFirstArray = 1000;  // array id of node n's external load: kFirstArray + n
constexpr int kFirstSchedule = 2000;  // array id of node n's power schedule: kFirstSchedule + n

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

void write_sinda_network(const std::filesystem::path& path, const ExportedNetwork& e,
                         const std::vector<std::filesystem::path>& protected_inputs) {
  const ThermalNetwork& net = e.network;
  const int n = net.num_nodes(), S = static_cast<int>(e.times_s.size());
  const bool tables = e.transient && S > 1;
  const Eigen::MatrixXd external = tables ? e.table_external_W() : e.external_W();
  const int K = static_cast<int>(e.table_times_s.size());
  write_file_atomically(path, [&](std::ostream& out) {
    out << "C thermodec export: SINDA/FLUINT thermal network\n"
           "C source: " << one_line(e.title) << "\n"
           "C units: SI (K, W, J/K, W/K, m^2, s); ABSZRO = 0 so T is absolute [K]\n"
           "C radiation conductors (negative id): G = GR [m^2] = sum A eps B; SINDA applies SIGMA\n"
           "C node n = thermodec node n - 1; " << kSpaceNode << " = deep space (boundary)\n"
           "C Q: internal power + absorbed solar, albedo and Earth IR [W], "
        << (tables ? "cyclic tables over one orbit, linear between points, both sides of each eclipse switch"
                   : "orbit-averaged (steady)") << "\n";
    if (tables && (has_power_schedules(net) || !net.heaters.empty()))
      out << "C internal power schedules: arrays " << kFirstSchedule << " + n; thermostat heaters: register HTRn (1 = on),\n"
             "C on below HONn, off above HOFn [K], adding HPWn [W], switched in VARIABLES 1\n";
    if (tables)
      out << "C initial temperatures: the orbit-periodic state at t = 0 (thermodec simulate); TRANSIENT runs\n"
             "C " << std::max(1, e.orbits) << " orbit(s) from it, every one of them the periodic orbit\n";
    for (const std::string& line : e.provenance) out << "C " << one_line(line) << "\n";
    out << "HEADER OPTIONS DATA\nTITLE thermodec export\n      OUTPUT = thermodec.out\n"
        << "HEADER CONTROL DATA, GLOBAL\n      UID    = SI\n      ABSZRO = 0.0\n      SIGMA  = 5.670374419E-8\n"
           "      NLOOPS = 1000\n      EBALSA = 1.0E-6\n";
    if (tables)
      out << "      TIMEO  = 0.0\n      TIMEND = " << real(e.period_s * std::max(1, e.orbits)) << "\n      DTIMEI = "
          << real(e.period_s / S) << "\n      OUTPUT = " << real(e.period_s / S) << "\n";
    if (tables && !net.heaters.empty()) {
      out << "HEADER REGISTER DATA\n";
      for (const NetworkHeater& h : net.heaters) {
        const std::string k = std::to_string(h.node + 1);
        out << "      HTR" << k << " = " << (e.temperature_K(h.node, 0) < h.thermostat.on_K ? "1.0" : "0.0") << "\n      HON" << k
            << " = " << real(h.thermostat.on_K) << "\n      HOF" << k << " = " << real(h.thermostat.off_K) << "\n      HPW" << k
            << " = " << real(h.thermostat.power_W) << "\n";
      }
    }
    out << "HEADER NODE DATA, MAIN\n";
    for (int i = 0; i < n; ++i) {
      // Boundary nodes: negative id; arithmetic and boundary: capacitance -1.0 (SINDA ignores it).
      const bool fixed = net.is_fixed(i);
      const double c = !fixed && net.capacitance_J_per_K[i] > 0.0 ? net.capacitance_J_per_K[i] : -1.0;
      out << "      " << (fixed ? "-" : "") << i + 1 << ", " << real(fixed ? net.fixed_temperature_K[i] : e.temperature_K(i, 0))
          << ", " << real(c) << "   $ " << one_line(net.node_names[i]) << "\n";
    }
    out << "      -" << kSpaceNode << ", " << real(net.sink_temperature_K) << ", -1.0   $ deep space\n"
        << "HEADER CONDUCTOR DATA, MAIN\n";
    int id = 1;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (net.conductance_W_per_K(i, j) != 0.0)
          out << "      " << id++ << ", " << i + 1 << ", " << j + 1 << ", " << real(net.conductance_W_per_K(i, j)) << "\n";
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (net.radiative_couplings_m2(i, j) != 0.0)
          out << "      -" << id++ << ", " << i + 1 << ", " << j + 1 << ", " << real(net.radiative_couplings_m2(i, j)) << "\n";
    for (int i = 0; i < n; ++i)
      if (net.to_space_couplings_m2[i] != 0.0)
        out << "      -" << id++ << ", " << i + 1 << ", " << kSpaceNode << ", " << real(net.to_space_couplings_m2[i]) << "\n";
    if (tables) {
      out << "HEADER ARRAY DATA, MAIN\nC doublets (time [s], absorbed external load [W]); the first point repeated at the period\n";
      for (int i = 0; i < n; ++i) {
        out << "      " << kFirstArray + i + 1 << " =";
        for (int k = 0; k <= K; ++k)
          out << (k ? "\n            , " : " ") << real(k < K ? e.table_times_s[k] : e.period_s) << ", " << real(external(i, k % K));
        out << "\n";
      }
      for (int i = 0; i < n; ++i)
        if (i < static_cast<int>(net.power_schedule_W.size()) && !net.power_schedule_W[i].empty()) {
          const auto d = schedule_doublets(net.power_schedule_W[i], e.period_s);
          out << "      " << kFirstSchedule + i + 1 << " =";
          for (std::size_t k = 0; k < d.size(); ++k) out << (k ? "\n            , " : " ") << real(d[k].first) << ", " << real(d[k].second);
          out << "\n";
        }
    }
    out << "HEADER VARIABLES 1, MAIN\n";
    for (int i = 0; i < n; ++i) {
      if (net.is_fixed(i)) continue;
      const bool scheduled = tables && i < static_cast<int>(net.power_schedule_W.size()) && !net.power_schedule_W[i].empty();
      if (scheduled)
        out << "      Q" << i + 1 << " = D11CYL(TIMEN, A" << kFirstSchedule + i + 1 << ", " << real(e.period_s) << ")\n"
            << "      Q" << i + 1 << " = Q" << i + 1 << " + D11CYL(TIMEN, A" << kFirstArray + i + 1 << ", " << real(e.period_s) << ")\n";
      else
        out << "      Q" << i + 1 << " = " << real(net.power_W[i]);
      if (scheduled) {
      } else if (tables)
        out << " + D11CYL(TIMEN, A" << kFirstArray + i + 1 << ", " << real(e.period_s) << ")\n";
      else
        out << " + " << real(external(i, 0)) << "\n";
      for (const NetworkHeater& h : net.heaters)
        if (tables && h.node == i) {
          const std::string k = std::to_string(i + 1);
          out << "      IF (T" << k << " .LT. HON" << k << ") HTR" << k << " = 1.0\n"
              << "      IF (T" << k << " .GT. HOF" << k << ") HTR" << k << " = 0.0\n"
              << "      Q" << k << " = Q" << k << " + HTR" << k << " * HPW" << k << "\n";
        }
    }
    // A transient starts from the periodic state above (a STEADY first would replace it with the
    // steady state of the loads at t = 0, several orbits away from periodicity).
    out << "HEADER OPERATIONS\nBUILD ALL\n" << (tables ? "      CALL TRANSIENT\n" : "      CALL STEADY\n");
    out << "END OF DATA\n";
  }, protected_inputs);
}

}  // namespace thermodec
