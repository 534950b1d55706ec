// Orbit transient converged in time: load interpolation between ray-traced positions, eclipse
// switches on step boundaries, backward Euler + Richardson extrapolation with a step-doubling
// error estimate (Hairer, Norsett & Wanner, "Solving ODEs I", II.4 and II.9: extrapolation of
// the implicit Euler method keeps its L-stability; the Richardson difference estimates the
// error of the less refined term).
#include "thermodec/thermal/orbit_transient.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec {

Eigen::VectorXd eclipse_switch_times_s(const Environment& env, double period_s) {
  // The shadow is a single arc per orbit (cylinder): scan finely enough to see any arc longer
  // than 1/720 of the orbit (shorter ones change no temperature measurably), then bisect.
  constexpr int kScan = 720;
  auto shadow = [&](double t) { return orbit_state(env, t).in_shadow; };
  std::vector<double> out;
  bool prev = shadow(0.0);
  for (int k = 1; k <= kScan; ++k) {
    double lo = period_s * (k - 1) / kScan, hi = period_s * k / kScan;
    const bool cur = shadow(k == kScan ? 0.0 : hi);
    if (cur == prev) continue;
    while (hi - lo > 1e-9 * period_s) {
      const double mid = 0.5 * (lo + hi);
      (shadow(mid) == prev ? lo : hi) = mid;
    }
    out.push_back(hi < period_s ? hi : 0.0);
    prev = cur;
  }
  std::sort(out.begin(), out.end());
  return Eigen::Map<Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size()));
}

namespace {

// Shadow state over the step ending at t (left limit; t = 0 is the end of the orbit).
bool shadow_before(double t, double period_s, bool shadow_at_0, const Eigen::VectorXd& switches) {
  if (t <= 0.0) t = period_s;
  int n = 0;
  for (int i = 0; i < switches.size(); ++i) n += switches[i] > 0.0 && switches[i] < t;
  return shadow_at_0 != (n % 2 == 1);
}

}  // namespace

Eigen::MatrixXd interpolated_loads_W(const Loads& loads, const Eigen::VectorXd& times_s,
                                     const Eigen::VectorXd& switches) {
  const int S = loads.num_steps();
  const double P = loads.period_s, dt = P / S;
  const Eigen::MatrixXd smooth = loads.albedo_W + loads.earth_ir_W;
  const Eigen::MatrixXd sun = loads.solar_W + loads.reflected_solar_W;
  const int n = static_cast<int>(smooth.rows());
  auto sh = [&](int k) { return static_cast<int>(S == static_cast<int>(loads.in_shadow.size()) && loads.in_shadow[(k + S) % S]); };
  const bool shadow0 = sh(0);
  Eigen::MatrixXd out(n, times_s.size());
  for (int c = 0; c < times_s.size(); ++c) {
    const double t = times_s[c];
    const int i = std::min(S - 1, static_cast<int>(std::floor(t / dt)));
    const double f = t / dt - i;
    const int j = (i + 1) % S;
    out.col(c) = (1.0 - f) * smooth.col(i) + f * smooth.col(j);
    const int s = shadow_before(t, P, shadow0, switches);
    // A sample at the instant itself (f = 0) stands for it when it shares the state.
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    const int p = (i - 1 + S) % S, q = (j + 1) % S;
    if (sh(i) == s && sh(j) == s) v = (1.0 - f) * sun.col(i) + f * sun.col(j);
    else if (sh(i) == s) v = sh(p) == s ? Eigen::VectorXd(sun.col(i) + f * (sun.col(i) - sun.col(p))) : Eigen::VectorXd(sun.col(i));
    else if (sh(j) == s) v = sh(q) == s ? Eigen::VectorXd(sun.col(j) + (1.0 - f) * (sun.col(j) - sun.col(q))) : Eigen::VectorXd(sun.col(j));
    out.col(c) += v.cwiseMax(0.0);  // extrapolation must not make an absorbed power negative
  }
  return out;
}

namespace {

// Solver grid: every load interval, split at the shadow switches inside it, each piece cut into
// max(1, round(substeps x its share of the interval)) x 2^level equal steps. `at_load[k]`: grid index of
// load position k. Halving every step (substeps x 2) keeps the switches and positions on the grid.
struct Grid {
  Eigen::VectorXd times_s;
  std::vector<int> at_load;
};

Grid solver_grid(int S, double P, const Eigen::VectorXd& switches, int substeps, int level) {
  const double dt = P / S;
  Grid g;
  std::vector<double> t;
  for (int k = 0; k < S; ++k) {
    g.at_load.push_back(static_cast<int>(t.size()));
    std::vector<double> cuts{k * dt};
    for (int i = 0; i < switches.size(); ++i)
      if (switches[i] > k * dt + 1e-9 * P && switches[i] < (k + 1) * dt - 1e-9 * P) cuts.push_back(switches[i]);
    cuts.push_back((k + 1) * dt);
    for (size_t c = 0; c + 1 < cuts.size(); ++c) {
      // The coarsest grid's count times 2^level: every step of a level halves one of the last.
      const int m = std::max(1, static_cast<int>(std::lround(substeps * (cuts[c + 1] - cuts[c]) / dt))) << level;
      for (int s = 0; s < m; ++s) t.push_back(cuts[c] + (cuts[c + 1] - cuts[c]) * s / m);
    }
  }
  g.times_s = Eigen::Map<Eigen::VectorXd>(t.data(), static_cast<Eigen::Index>(t.size()));
  return g;
}

}  // namespace

OrbitTransient orbit_transient(const ThermalNetwork& network, const Loads& loads, const Eigen::VectorXd& switches,
                               const OrbitTimeSettings& time, const TransientSettings& settings) {
  const int S = loads.num_steps();
  const double P = loads.period_s;
  if (S < 2 || !(P > 0.0)) throw InvalidInput("orbit transient: need >= 2 load positions and a period > 0 s");
  for (int k = 0; k < S; ++k)
    if (std::abs(loads.times_s[k] - k * P / S) > 1e-6 * P)
      throw InvalidInput("orbit transient: load positions must be at k P / S");
  if (!(time.time_tolerance_K > 0.0)) throw InvalidInput("orbit transient: time tolerance must be > 0 K");
  if (time.substeps < 1 || time.max_levels < 3) throw InvalidInput("orbit transient: substeps >= 1 and max_levels >= 3");

  auto solve_level = [&](int level, PeriodicTransient* full) {
    const Grid g = solver_grid(S, P, switches, time.substeps, level);
    PeriodicTransient tr =
        periodic_transient_on_grid(network, interpolated_loads_W(loads, g.times_s, switches), g.times_s, P, settings);
    Eigen::MatrixXd at(tr.temperature_K.rows(), S);
    for (int k = 0; k < S; ++k) at.col(k) = tr.temperature_K.col(g.at_load[k]);
    if (full) *full = std::move(tr);
    return std::make_pair(at, static_cast<int>(g.times_s.size()));
  };
  OrbitTransient out;
  out.eclipse_times_s = switches;
  PeriodicTransient finest;
  Eigen::MatrixXd T_prev = solve_level(0, nullptr).first;
  Eigen::MatrixXd R_prev;
  for (int level = 1; level < time.max_levels; ++level) {
    const auto [T, steps] = solve_level(level, &finest);
    const Eigen::MatrixXd R = 2.0 * T - T_prev;  // first-order error terms cancel
    out.solver_steps_per_orbit = steps;
    if (level >= 2) {
      // Asymptotically |R - R_prev| / 3 (second order); the whole difference is kept, a bound
      // that still holds while the grid is coarse enough for higher-order terms to matter.
      out.time_error_K = (R - R_prev).cwiseAbs().maxCoeff();
      if (out.time_error_K <= time.time_tolerance_K || level + 1 == time.max_levels) {
        out.transient = std::move(finest);
        out.transient.times_s = loads.times_s;
        out.transient.temperature_K = R;
        return out;
      }
    }
    T_prev = T;
    R_prev = R;
  }
  return out;  // unreachable (max_levels >= 3)
}

}  // namespace thermodec
