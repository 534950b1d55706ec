#pragma once
// Minimal readers of the ESATAN-TMS and SINDA/FLUINT files thermodec writes, written from the
// languages' block structure (not from the writers): they rebuild a ThermalNetwork and a load
// table so that the project's solver can integrate what the file says. A node, conductor or
// load missing from a file shows up as a temperature difference.
#include <Eigen/Core>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "thermodec/thermal/network.h"

namespace exchange_test {

struct ReadNetwork {
  thermodec::ThermalNetwork network;
  Eigen::VectorXd times_s;        // S table times over one orbit (steady: one 0)
  Eigen::MatrixXd external_W;     // N x S absorbed external loads
  double period_s = 0.0;
  bool transient = false;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Sizes the network for n thermal nodes (ids 1..n), deep space as the sink.
inline void size_network(thermodec::ThermalNetwork& net, int n) {
  net.node_names.assign(n, "");
  net.capacitance_J_per_K = Eigen::VectorXd::Zero(n);
  net.power_W = Eigen::VectorXd::Zero(n);
  net.fixed_temperature_K = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  net.conductance_W_per_K = Eigen::MatrixXd::Zero(n, n);
  net.radiative_couplings_m2 = Eigen::MatrixXd::Zero(n, n);
  net.to_space_couplings_m2 = Eigen::VectorXd::Zero(n);
}

// A Fortran real: E or D (double precision) exponent.
inline double fortran_double(std::string s) {
  for (char& c : s)
    if (c == 'D' || c == 'd') c = 'E';
  return std::stod(s);
}

// Every number in `text`, in order (e.g. a doublet table t0, v0, t1, v1, ...).
inline std::vector<double> numbers_in(const std::string& text) {
  static const std::regex number(R"([-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?)");
  std::vector<double> v;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it)
    v.push_back(fortran_double(it->str()));
  return v;
}

// Splits a file into blocks: ESATAN `$NAME` lines, SINDA `HEADER NAME` lines.
inline std::map<std::string, std::string> blocks(const std::string& text, const std::regex& header) {
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  std::string line, current;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, header)) {
      current = m[1];
      continue;
    }
    if (!line.empty() && (line[0] == '#' || (line[0] == 'C' && (line.size() == 1 || line[1] == ' ')))) continue;
    out[current] += line + "\n";
  }
  return out;
}

inline ReadNetwork read_esatan(const std::string& path) {
  const auto b = blocks(slurp(path), std::regex(R"(^\$([A-Z0-9]+))"));
  ReadNetwork r;
  static const std::regex node(R"(^([DAB])(\d+) = '([^']*)'(.*);)");
  static const std::regex attribute(R"(\b(T|C|QI|QS|QA|QE) = ([^,;]+))");
  std::map<int, std::map<std::string, double>> attrs;
  std::map<int, std::pair<char, std::string>> kinds;
  std::istringstream nodes(b.at("NODES"));
  for (std::string line; std::getline(nodes, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, node)) continue;
    const int id = std::stoi(m[2]);
    kinds[id] = {m[1].str()[0], m[3]};
    const std::string rest = m[4];
    for (auto it = std::sregex_iterator(rest.begin(), rest.end(), attribute); it != std::sregex_iterator(); ++it)
      attrs[id][(*it)[1]] = fortran_double((*it)[2]);
  }
  int n = 0;
  for (const auto& [id, k] : kinds)
    if (id != 99999) n = std::max(n, id);
  size_network(r.network, n);
  for (const auto& [id, k] : kinds) {
    if (id == 99999) { r.network.sink_temperature_K = attrs[id]["T"]; continue; }
    const int i = id - 1;
    r.network.node_names[i] = k.second;
    r.network.capacitance_J_per_K[i] = attrs[id]["C"];
    r.network.power_W[i] = attrs[id]["QI"];
    if (k.first == 'B') r.network.fixed_temperature_K[i] = attrs[id]["T"];
  }
  static const std::regex conductor(R"((GL|GR)\((\d+), (\d+)\) = ([^;]+);)");
  const std::string& cs = b.at("CONDUCTORS");
  for (auto it = std::sregex_iterator(cs.begin(), cs.end(), conductor); it != std::sregex_iterator(); ++it) {
    const int i = std::stoi((*it)[2]) - 1, j = std::stoi((*it)[3]) - 1;
    const double g = fortran_double((*it)[4]);
    if ((*it)[1] == "GL") r.network.conductance_W_per_K(i, j) += g, r.network.conductance_W_per_K(j, i) += g;
    else if (j == 99998) r.network.to_space_couplings_m2[i] += g;
    else r.network.radiative_couplings_m2(i, j) += g, r.network.radiative_couplings_m2(j, i) += g;
  }
  r.transient = b.count("VARIABLES1") > 0 && b.at("VARIABLES1").find("INTCY1") != std::string::npos;
  if (!r.transient) {
    r.times_s = Eigen::VectorXd::Zero(1);
    r.external_W = Eigen::MatrixXd::Zero(n, 1);
    for (int i = 0; i < n; ++i) r.external_W(i, 0) = attrs[i + 1]["QS"] + attrs[i + 1]["QA"] + attrs[i + 1]["QE"];
    return r;
  }
  // $CONSTANTS: PERIOD; $ARRAYS: name(count) = doublets; $VARIABLES1: QS(n) = INTCY1(TIMEM, name, PERIOD).
  std::smatch m;
  const std::string& constants = b.at("REAL");  // the first $REAL after $CONSTANTS holds PERIOD
  if (std::regex_search(constants, m, std::regex(R"(PERIOD = ([^;]+);)"))) r.period_s = fortran_double(m[1]);
  std::map<std::string, std::vector<double>> arrays;
  const std::string all = slurp(path);
  static const std::regex array(R"(([A-Z]+\d+)\(\d+\) =([^;]*);)");
  for (auto it = std::sregex_iterator(all.begin(), all.end(), array); it != std::sregex_iterator(); ++it)
    arrays[(*it)[1]] = numbers_in((*it)[2]);
  static const std::regex use(R"(Q[SAE]\((\d+)\) = INTCY1\(TIMEM, ([A-Z]+\d+), PERIOD\))");
  const std::string& vars = b.at("VARIABLES1");
  for (auto it = std::sregex_iterator(vars.begin(), vars.end(), use); it != std::sregex_iterator(); ++it) {
    const int i = std::stoi((*it)[1]) - 1;
    const std::vector<double>& d = arrays.at((*it)[2]);
    const int S = static_cast<int>(d.size() / 2) - 1;  // closing point at the period
    if (r.times_s.size() == 0) {
      r.times_s.resize(S);
      for (int k = 0; k < S; ++k) r.times_s[k] = d[2 * k];
      r.external_W = Eigen::MatrixXd::Zero(n, S);
    }
    for (int k = 0; k < S; ++k) r.external_W(i, k) += d[2 * k + 1];
  }
  return r;
}

inline ReadNetwork read_sinda(const std::string& path) {
  const auto b = blocks(slurp(path), std::regex(R"(^HEADER ([A-Z0-9 ]+?)(,|$))"));
  ReadNetwork r;
  struct Row { int id; double t, c; };
  std::vector<Row> rows;
  std::istringstream nodes(b.at("NODE DATA"));
  for (std::string line; std::getline(nodes, line);) {
    const std::string data = line.substr(0, line.find('$'));
    const auto v = numbers_in(data);
    if (v.size() == 3) rows.push_back({static_cast<int>(v[0]), v[1], v[2]});
  }
  int n = 0;
  for (const Row& row : rows)
    if (std::abs(row.id) != 99999) n = std::max(n, std::abs(row.id));
  size_network(r.network, n);
  for (const Row& row : rows) {
    if (std::abs(row.id) == 99999) { r.network.sink_temperature_K = row.t; continue; }
    const int i = std::abs(row.id) - 1;
    r.network.node_names[i] = std::to_string(i + 1);
    r.network.capacitance_J_per_K[i] = row.c > 0.0 ? row.c : 0.0;  // -1: arithmetic
    if (row.id < 0) r.network.fixed_temperature_K[i] = row.t;
  }
  std::istringstream conductors(b.at("CONDUCTOR DATA"));
  for (std::string line; std::getline(conductors, line);) {
    const auto v = numbers_in(line);
    if (v.size() != 4) continue;
    const int i = static_cast<int>(v[1]) - 1, j = static_cast<int>(v[2]) - 1;
    if (v[0] > 0) r.network.conductance_W_per_K(i, j) += v[3], r.network.conductance_W_per_K(j, i) += v[3];
    else if (j == 99998) r.network.to_space_couplings_m2[i] += v[3];
    else r.network.radiative_couplings_m2(i, j) += v[3], r.network.radiative_couplings_m2(j, i) += v[3];
  }
  std::map<int, std::vector<double>> arrays;
  if (b.count("ARRAY DATA")) {
    static const std::regex array(R"((\d+) =([^=]*?)(?=\n\s+\d+ =|$))");
    const std::string& a = b.at("ARRAY DATA");
    for (auto it = std::sregex_iterator(a.begin(), a.end(), array); it != std::sregex_iterator(); ++it)
      arrays[std::stoi((*it)[1])] = numbers_in((*it)[2]);
  }
  r.transient = !arrays.empty();
  static const std::regex q(R"(Q(\d+) = ([^ ]+) \+ (D11CYL\(TIMEN, A(\d+), ([^)]+)\)|(\S+)))");
  const std::string& vars = b.at("VARIABLES 1");
  for (auto it = std::sregex_iterator(vars.begin(), vars.end(), q); it != std::sregex_iterator(); ++it) {
    const int i = std::stoi((*it)[1]) - 1;
    r.network.power_W[i] = std::stod((*it)[2]);
    if ((*it)[4].matched) {
      r.period_s = std::stod((*it)[5]);
      const std::vector<double>& d = arrays.at(std::stoi((*it)[4]));
      const int S = static_cast<int>(d.size() / 2) - 1;
      if (r.times_s.size() == 0) {
        r.times_s.resize(S);
        for (int k = 0; k < S; ++k) r.times_s[k] = d[2 * k];
        r.external_W = Eigen::MatrixXd::Zero(n, S);
      }
      for (int k = 0; k < S; ++k) r.external_W(i, k) = d[2 * k + 1];
    } else {
      if (r.times_s.size() == 0) r.times_s = Eigen::VectorXd::Zero(1), r.external_W = Eigen::MatrixXd::Zero(n, 1);
      r.external_W(i, 0) = std::stod((*it)[6]);
    }
  }
  return r;
}

}  // namespace exchange_test
