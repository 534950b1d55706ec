// ESATAN-TMS network writer. Syntax as in the .d files ESATAN-TMS itself generates: data blocks
// ($NODES, $CONDUCTORS, $CONSTANTS, $ARRAYS) of `;`-terminated entries (`D1 = 'label', T = ...,
// C = ..., A = ..., ALP = ..., EPS = ...;`, `GL(1, 2) = ...;`), reals with Fortran D exponents
// (double precision also where they reach the generated Fortran), `#` comment lines; operation
// blocks ($EXECUTION, $VARIABLES1, $OUTPUTS) as Fortran statements from column 7, a node's
// entity referenced as QS(n), routines called with CALL, blocks in ESATAN-TMS's order.
#include "thermodec/exchange/write_esatan_network.h"

#include <ostream>

#include "number_text.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/thermal/internal_power.h"

namespace thermodec {
namespace {

// ESATAN-TMS writes reals with a D exponent (`5.D-03`): double precision in the Fortran it generates.
std::string real(double x) {
  std::string s = exchange_text::fortran_real(x);
  for (char& c : s)
    if (c == 'E') c = 'D';
  return s;
}
constexpr int kSpaceNode = 99999;

std::string quoted(std::string s) {  // ESATAN labels are single-quoted; a quote is doubled
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

// One cyclic doublet table (time [s], load [W]) over [0, P]: the first point repeated at P,
// so the interpolation wraps around the orbit. The table's points (ExportedNetwork::table_*)
// hold both sides of every eclipse switch.
void write_table(std::ostream& out, const std::string& name, const ExportedNetwork& e, const Eigen::MatrixXd& load, int node) {
  const int K = static_cast<int>(e.table_times_s.size());
  out << name << "(" << 2 * (K + 1) << ") =\n";
  for (int k = 0; k <= K; ++k) {
    const double t = k < K ? e.table_times_s[k] : e.period_s;
    out << "    " << real(t) << ", " << real(load(node, k % K)) << (k < K ? ",\n" : ";\n");
  }
}

// Doublet array of a node's power schedule (schedule_doublets).
void write_schedule(std::ostream& out, const std::string& name, const std::vector<std::pair<double, double>>& d) {
  out << name << "(" << 2 * d.size() << ") =\n";
  for (std::size_t k = 0; k < d.size(); ++k)
    out << "    " << real(d[k].first) << ", " << real(d[k].second) << (k + 1 < d.size() ? ",\n" : ";\n");
}

// $VARIABLES1 lines of node i's internal power: its schedule (INTCY1 over the doublets QINTi)
// and its thermostat heater (state HTRi switched on below HONi, off above HOFi, power HPWi),
// evaluated as ESATAN evaluates $VARIABLES1, once per solution step.
void write_internal_power(std::ostream& out, const ThermalNetwork& net, int i) {
  const std::string k = std::to_string(i + 1);
  const bool scheduled = i < static_cast<int>(net.power_schedule_W.size()) && !net.power_schedule_W[i].empty();
  const NetworkHeater* heater = nullptr;
  for (const NetworkHeater& h : net.heaters)
    if (h.node == i) heater = &h;
  if (scheduled) out << "      QI(" << k << ") = INTCY1(TIMEM, QINT" << k << ", PERIOD)\n";
  if (!heater) return;
  if (!scheduled) out << "      QI(" << k << ") = " << real(net.power_W[i]) << "\n";
  out << "      IF (T(" << k << ") .LT. HON" << k << ") HTR" << k << " = 1\n"
      << "      IF (T(" << k << ") .GT. HOF" << k << ") HTR" << k << " = 0\n"
      << "      IF (HTR" << k << " .EQ. 1) QI(" << k << ") = QI(" << k << ") + HPW" << k << "\n";
}

}  // namespace

void write_esatan_network(const std::filesystem::path& path, const ExportedNetwork& e,
                          const std::vector<std::filesystem::path>& protected_inputs) {
  const ThermalNetwork& net = e.network;
  const int n = net.num_nodes(), S = static_cast<int>(e.times_s.size());
  const bool tables = e.transient && S > 1;
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# thermodec export: ESATAN-TMS thermal network\n"
           "# source: " << e.title << "\n"
           "# units: SI (m^2, K, W, J/K, W/K, s); TABS = 0 so T is absolute [K]\n"
           "# GR(i, j) [m^2] = sum A eps B (emissivities included); ESATAN multiplies by STEFAN\n"
           "# node n = thermodec node n - 1; " << kSpaceNode << " = deep space (boundary, " << real(net.sink_temperature_K) << " K)\n"
           "# loads: QS = direct + reflected solar, QA = albedo, QE = Earth IR [W], "
        << (tables ? "cyclic tables over one orbit, linear between points, both sides of each eclipse switch" : "orbit-averaged (steady)") << "\n";
    if (tables && (has_power_schedules(net) || !net.heaters.empty()))
      out << "# QI: internal power [W]; a schedule as the cyclic table QINTn; a thermostat heater as\n"
             "# state HTRn (1 = on), on below HONn, off above HOFn [K], adding HPWn [W]\n";
    for (const std::string& line : e.provenance) out << "# " << line << "\n";
    out << "$MODEL THERMODEC\n$LOCALS\n$NODES\n";
    const Eigen::MatrixXd& T = e.temperature_K;
    for (int i = 0; i < n; ++i) {
      const char type = net.is_fixed(i) ? 'B' : net.capacitance_J_per_K[i] > 0.0 ? 'D' : 'A';
      out << type << i + 1 << " = " << quoted(net.node_names[i]) << ", T = " << real(net.is_fixed(i) ? net.fixed_temperature_K[i] : T(i, 0))
          << ", C = " << real(net.capacitance_J_per_K[i]) << ", A = " << real(e.area_m2[i]) << ", ALP = " << real(e.absorptivity[i])
          << ", EPS = " << real(e.emissivity[i]) << ", QI = " << real(net.power_W[i]);
      if (!tables)
        out << ", QS = " << real(e.solar_W(i, 0)) << ", QA = " << real(e.albedo_W(i, 0)) << ", QE = " << real(e.earth_ir_W(i, 0));
      out << ";\n";
    }
    out << "B" << kSpaceNode << " = 'deep space', T = " << real(net.sink_temperature_K) << ";\n$CONDUCTORS\n";
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (net.conductance_W_per_K(i, j) != 0.0) out << "GL(" << i + 1 << ", " << j + 1 << ") = " << real(net.conductance_W_per_K(i, j)) << ";\n";
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (net.radiative_couplings_m2(i, j) != 0.0) out << "GR(" << i + 1 << ", " << j + 1 << ") = " << real(net.radiative_couplings_m2(i, j)) << ";\n";
    for (int i = 0; i < n; ++i)
      if (net.to_space_couplings_m2[i] != 0.0) out << "GR(" << i + 1 << ", " << kSpaceNode << ") = " << real(net.to_space_couplings_m2[i]) << ";\n";
    out << "$CONSTANTS\n";
    if (tables && !net.heaters.empty()) {
      out << "$INTEGER\n";
      for (const NetworkHeater& h : net.heaters)  // initial state: from the initial temperature
        out << "HTR" << h.node + 1 << " = " << (T(h.node, 0) < h.thermostat.on_K ? 1 : 0) << ";\n";
    }
    out << "$REAL\nPERIOD = " << real(e.period_s) << ";\n";
    if (tables)
      for (const NetworkHeater& h : net.heaters) {
        const std::string k = std::to_string(h.node + 1);
        out << "HON" << k << " = " << real(h.thermostat.on_K) << ";\nHOF" << k << " = " << real(h.thermostat.off_K)
            << ";\nHPW" << k << " = " << real(h.thermostat.power_W) << ";\n";
      }
    out << "$CONTROL\nTABS = 0.0;\nSTEFAN = 5.670374419D-8;\n"
           "RELXCA = 1.0D-6;\nRELXCB = 1.0D-6;\nNLOOP = 1000;\n";
    if (tables) {
      const double dt = e.period_s / S;
      out << "TIMEO = 0.0;\nTIMEND = " << real(e.period_s) << ";\nDTIMEI = " << real(dt) << ";\nOUTINT = " << real(dt)
          << ";\n$ARRAYS\n$REAL\n";
      for (int i = 0; i < n; ++i) {
        write_table(out, "QSOL" + std::to_string(i + 1), e, e.table_solar_W, i);
        write_table(out, "QALB" + std::to_string(i + 1), e, e.table_albedo_W, i);
        write_table(out, "QEIR" + std::to_string(i + 1), e, e.table_earth_ir_W, i);
        if (i < static_cast<int>(net.power_schedule_W.size()) && !net.power_schedule_W[i].empty())
          write_schedule(out, "QINT" + std::to_string(i + 1), schedule_doublets(net.power_schedule_W[i], e.period_s));
      }
    } else {
      out << "$ARRAYS\n";
    }
    out << "$EVENTS\n$SUBROUTINES\n$INITIAL\n$EXECUTION\n      CALL SOLVFM\n";
    if (tables)
      // The orbit-periodic state: SOLCYC repeats SLCRNC (Crank-Nicolson) over the period until
      // the cycle converges, then SLCRNC runs the output orbit. Written as ESATAN-TMS's own case
      // generator writes it (tolerances 0.01, at most 100 cycles).
      out << "      CALL SOLCYC('SLCRNC', 0.01D0, 0.01D0, PERIOD, 100, ' ', 'NONE')\n      CALL SLCRNC\n";
    out << "$VARIABLES1\n";
    if (tables) {
      out << "# loads at the orbit time TIMEM: cyclic linear interpolation of the doublet tables\n";
      for (int i = 0; i < n; ++i) {
        const std::string k = std::to_string(i + 1);
        out << "      QS(" << k << ") = INTCY1(TIMEM, QSOL" << k << ", PERIOD)\n"
            << "      QA(" << k << ") = INTCY1(TIMEM, QALB" << k << ", PERIOD)\n"
            << "      QE(" << k << ") = INTCY1(TIMEM, QEIR" << k << ", PERIOD)\n";
        write_internal_power(out, net, i);
      }
    }
    out << "$VARIABLES2\n$OUTPUTS\n      CALL PRNDTB(' ', 'L, T, QS, QA, QE, QI, C', CURRENT)\n$ENDMODEL THERMODEC\n";
  }, protected_inputs);
}

}  // namespace thermodec
