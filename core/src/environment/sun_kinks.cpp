// Kinks of the direct sun between orbit positions (see sun_kinks.h). The sun's direction in body
// axes is smooth, so each side's n . s is a smooth function of time; its zero crossings, found on
// a grid 16 times finer than the positions and placed by linear interpolation of n . s, are
// where max(0, n . s) kinks.
#include "sun_kinks.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace thermodec::load_rays {

std::vector<double> sun_kink_times_s(const ThermalModel& model, const std::vector<Side>& sides,
                                     const std::vector<int>& node_of_side, const Eigen::VectorXd& alpha, double flux,
                                     int positions, double threshold_K, int max_knots) {
  std::vector<double> out;
  if (positions < 2 || max_knots < 1 || !(flux > 0.0) || !(threshold_K > 0.0)) return out;
  constexpr int kFine = 16;
  const double P = orbit_period_s(model.environment), h = P / positions, dt = h / kFine;
  const int M = positions * kFine;
  std::vector<Eigen::Vector3d> sun(M);
  std::vector<char> lit(M);
  for (int m = 0; m < M; ++m) {
    const OrbitState st = orbit_state(model.environment, m * dt);
    sun[m] = st.sun_direction_body;
    lit[m] = !st.in_shadow;
  }
  const int N = static_cast<int>(model.nodes.size());
  // Per fine cell: per node, summed slope jump [W/s] and slope-jump-weighted crossing time.
  std::map<int, std::vector<std::pair<double, double>>> cells;
  for (std::size_t s = 0; s < sides.size(); ++s) {
    const int node = node_of_side[s];
    if (node < 0 || node >= N || model.nodes[node].fixed_temperature_K) continue;
    const double w = flux * alpha[static_cast<Eigen::Index>(s)] * sides[s].area;
    if (!(w > 0.0)) continue;
    for (int m = 0; m < M; ++m) {
      const int next = (m + 1) % M;
      if (m % kFine == 0 || !lit[m] || !lit[next]) continue;  // a cell starting at a position is held by it
      const double a = sides[s].normal.dot(sun[m]), b = sides[s].normal.dot(sun[next]);
      if ((a > 0.0) == (b > 0.0)) continue;
      const double t = m * dt + dt * a / (a - b);
      const double jump = w * std::abs(b - a) / dt;
      auto& cell = cells[m];
      if (cell.empty()) cell.assign(N, {0.0, 0.0});
      cell[node].first += jump;
      cell[node].second += jump * t;
    }
  }
  std::vector<std::pair<double, double>> scored;  // (figure [K], time)
  for (const auto& [m, per_node] : cells) {
    double worst = 0.0, weight = 0.0, time = 0.0;
    for (int i = 0; i < N; ++i) {
      const double J = per_node[i].first;
      if (!(J > 0.0)) continue;
      const double c = model.nodes[i].capacitance_J_per_K;
      const double figure = c > 0.0 ? J * h * h / (8.0 * c) : 2.0 * threshold_K;  // arithmetic: any kink shows
      worst = std::max(worst, figure);
      weight += figure;
      time += figure * per_node[i].second / J;
    }
    if (worst > threshold_K && weight > 0.0) scored.emplace_back(worst, time / weight);
  }
  std::sort(scored.begin(), scored.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  if (static_cast<int>(scored.size()) > max_knots) scored.resize(max_knots);
  for (const auto& sc : scored) out.push_back(sc.second);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace thermodec::load_rays
