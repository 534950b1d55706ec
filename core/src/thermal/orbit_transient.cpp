// Orbit transient converged in time: load interpolation between ray-traced positions, eclipse
// switches on step boundaries, backward Euler + Richardson extrapolation with a step-doubling
// error estimate (Hairer, Norsett & Wanner, "Solving ODEs I", II.4 and II.9: extrapolation of
// the implicit Euler method keeps its L-stability; the Richardson difference estimates the
// error of the less refined term).
#include "thermodec/thermal/orbit_transient.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/thermal/internal_power.h"

namespace thermodec {

namespace {

// Sum of the components that are (direct_sun) or are not switched at the eclipse, in table order.
Eigen::MatrixXd sum_of(const Loads& loads, bool direct_sun, bool knots) {
  Eigen::MatrixXd t;
  for (const LoadComponent& c : load_components()) {
    if (c.direct_sun != direct_sun) continue;
    const Eigen::MatrixXd& m = loads.*(knots ? c.knot_W : c.W);
    if (t.size() == 0) t = m;
    else t += m;
  }
  return t;
}

// Shadow state over the step ending at t (left limit; t = 0 is the end of the orbit).
bool shadow_before(double t, double period_s, bool shadow_at_0, const Eigen::VectorXd& switches) {
  if (t <= 0.0) t = period_s;
  int n = 0;
  for (int i = 0; i < switches.size(); ++i) n += switches[i] > 0.0 && switches[i] < t;
  return shadow_at_0 != (n % 2 == 1);
}

// Cyclic piecewise-linear interpolation over knots (times in [0, P), any order; columns of v)
// at t in [0, P].
class CyclicKnots {
 public:
  CyclicKnots(std::vector<double> t, Eigen::MatrixXd v, double P) : P_(P), v_(std::move(v)) {
    order_.resize(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) order_[k] = static_cast<int>(k);
    std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) { return t[a] < t[b]; });
    for (const int k : order_) t_.push_back(t[k]);
  }
  bool empty() const { return t_.empty(); }
  Eigen::VectorXd at(double t) const {
    const int n = static_cast<int>(t_.size());
    const int r = static_cast<int>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());
    const int l = r - 1;
    const double tl = l >= 0 ? t_[l] : t_[n - 1] - P_, tr = r < n ? t_[r] : t_[0] + P_;
    const Eigen::VectorXd vl = v_.col(order_[(l + n) % n]), vr = v_.col(order_[r % n]);
    if (!(tr > tl)) return vl;
    const double w = (t - tl) / (tr - tl);
    return (1.0 - w) * vl + w * vr;
  }

 private:
  double P_;
  Eigen::MatrixXd v_;
  std::vector<int> order_;
  std::vector<double> t_;
};

// With sunlit knots (Loads::knot_*): the smooth part (albedo, Earth IR) interpolated over positions
// and knots, the sunlit arcs' direct-sun part over the sunlit positions and the knots, among them
// the eclipse edges that bound each arc.
struct SunlitKnots {
  CyclicKnots smooth, sunlit;
};

SunlitKnots sunlit_knots(const Loads& loads) {
  const int S = loads.num_steps(), E = static_cast<int>(loads.knot_times_s.size());
  const double dt = loads.period_s / S;
  std::vector<double> all_t, lit_t;
  Eigen::MatrixXd all_v(loads.solar_W.rows(), S + E), lit_v(loads.solar_W.rows(), S + E);
  const Eigen::MatrixXd smooth = sum_of(loads, false, false), sun = sum_of(loads, true, false);
  const Eigen::MatrixXd knot_smooth = sum_of(loads, false, true), knot_sun = sum_of(loads, true, true);
  for (int k = 0; k < S; ++k) {
    all_v.col(static_cast<Eigen::Index>(all_t.size())) = smooth.col(k);
    all_t.push_back(k * dt);
    if (static_cast<int>(loads.in_shadow.size()) == S && loads.in_shadow[k]) continue;
    lit_v.col(static_cast<Eigen::Index>(lit_t.size())) = sun.col(k);
    lit_t.push_back(k * dt);
  }
  for (int e = 0; e < E; ++e) {
    all_v.col(static_cast<Eigen::Index>(all_t.size())) = knot_smooth.col(e);
    all_t.push_back(loads.knot_times_s[e]);
    lit_v.col(static_cast<Eigen::Index>(lit_t.size())) = knot_sun.col(e);
    lit_t.push_back(loads.knot_times_s[e]);
  }
  all_v.conservativeResize(Eigen::NoChange, static_cast<Eigen::Index>(all_t.size()));
  lit_v.conservativeResize(Eigen::NoChange, static_cast<Eigen::Index>(lit_t.size()));
  return {CyclicKnots(all_t, all_v, loads.period_s), CyclicKnots(lit_t, lit_v, loads.period_s)};
}

}  // namespace

Eigen::MatrixXd interpolated_loads_W(const Loads& loads, const Eigen::VectorXd& times_s,
                                     const Eigen::VectorXd& switches) {
  const int S = loads.num_steps();
  const double P = loads.period_s, dt = P / S;
  const Eigen::MatrixXd smooth = sum_of(loads, false, false);
  const Eigen::MatrixXd sun = sum_of(loads, true, false);
  const int n = static_cast<int>(smooth.rows());
  auto sh = [&](int k) { return static_cast<int>(S == static_cast<int>(loads.in_shadow.size()) && loads.in_shadow[(k + S) % S]); };
  const bool shadow0 = sh(0);
  const bool edges = loads.has_knots() && loads.knot_solar_W.rows() == n;
  const SunlitKnots knots = edges ? sunlit_knots(loads) : SunlitKnots{CyclicKnots({}, {}, P), CyclicKnots({}, {}, P)};
  Eigen::MatrixXd out(n, times_s.size());
  for (int c = 0; c < times_s.size(); ++c) {
    const double t = times_s[c];
    const int i = std::min(S - 1, static_cast<int>(std::floor(t / dt)));
    const double f = t / dt - i;
    const int j = (i + 1) % S;
    out.col(c) = edges ? knots.smooth.at(t) : Eigen::VectorXd((1.0 - f) * smooth.col(i) + f * smooth.col(j));
    const int s = shadow_before(t, P, shadow0, switches);
    if (edges && !s) {  // a sunlit arc passes through its knots and ends on its traced edges
      out.col(c) += knots.sunlit.at(t <= 0.0 ? P : t).cwiseMax(0.0);
      continue;
    }
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
      if (switches[i] > k * dt + 1e-9 * P && switches[i] < (k + 1) * dt - 1e-9 * P && switches[i] > cuts.back() + 1e-9 * P)
        cuts.push_back(switches[i]);
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

  // Step boundaries: the eclipse switches and the instants where a power schedule changes.
  const bool schedules = has_power_schedules(network);
  Eigen::VectorXd cuts = switches;
  if (schedules) {
    const Eigen::VectorXd power_switches = power_switch_times_s(network, P);
    std::vector<double> all(switches.data(), switches.data() + switches.size());
    all.insert(all.end(), power_switches.data(), power_switches.data() + power_switches.size());
    std::sort(all.begin(), all.end());
    cuts = Eigen::Map<const Eigen::VectorXd>(all.data(), static_cast<Eigen::Index>(all.size()));
  }
  Eigen::VectorXd heater_mean_W;
  auto solve_level = [&](int level, PeriodicTransient* full) {
    const Grid g = solver_grid(S, P, cuts, time.substeps, level);
    Eigen::MatrixXd applied = interpolated_loads_W(loads, g.times_s, switches);
    if (schedules) applied += scheduled_power_W(network, g.times_s, P);
    PeriodicTransient tr = periodic_transient_on_grid(network, applied, g.times_s, P, settings);
    Eigen::MatrixXd at(tr.temperature_K.rows(), S);
    for (int k = 0; k < S; ++k) at.col(k) = tr.temperature_K.col(g.at_load[k]);
    if (full && tr.heater_power_W.cols() == g.times_s.size()) {
      // Orbit mean over the grid (column c: the step ending at times_s[c]), then the power at
      // the load positions.
      const Eigen::Index K = g.times_s.size();
      heater_mean_W = Eigen::VectorXd::Zero(tr.heater_power_W.rows());
      for (Eigen::Index c = 0; c < K; ++c)
        heater_mean_W += tr.heater_power_W.col(c) * ((c > 0 ? g.times_s[c] : P) - g.times_s[(c + K - 1) % K]) / P;
      Eigen::MatrixXd h(tr.heater_power_W.rows(), S);
      for (int k = 0; k < S; ++k) h.col(k) = tr.heater_power_W.col(g.at_load[k]);
      tr.heater_power_W = h;
    }
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
        out.heater_mean_W = heater_mean_W;
        return out;
      }
    }
    T_prev = T;
    R_prev = R;
  }
  return out;  // unreachable (max_levels >= 3)
}

Loads loads_at(const Loads& loads, const Eigen::VectorXd& times_s, const Eigen::VectorXd& switches) {
  // One component at a time (the others zeroed): the interpolation is linear in the loads.
  const auto& parts = load_components();
  Loads out;
  out.period_s = loads.period_s;
  out.times_s = times_s;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    Loads one = loads;
    for (std::size_t q = 0; q < parts.size(); ++q) {
      if (q == p) continue;
      (one.*(parts[q].W)).setZero();
      (one.*(parts[q].knot_W)).setZero();
    }
    out.*(parts[p].W) = interpolated_loads_W(one, times_s, switches);
  }
  out.in_shadow.assign(static_cast<std::size_t>(times_s.size()), 0);
  return out;
}

Loads orbit_mean_loads(const Loads& loads, const Eigen::VectorXd& switches) {
  const int S = loads.num_steps();
  const double P = loads.period_s;
  if (S < 2 || !(P > 0.0)) throw InvalidInput("orbit mean of the loads: need >= 2 positions and a period > 0 s");
  // Breakpoints of the piecewise-linear interpolant: positions, switches, knots. The midpoint
  // rule is exact on each piece.
  std::vector<double> cuts;
  for (int k = 0; k <= S; ++k) cuts.push_back(P * k / S);
  for (Eigen::Index i = 0; i < switches.size(); ++i) cuts.push_back(switches[i]);
  for (Eigen::Index i = 0; i < loads.knot_times_s.size(); ++i) cuts.push_back(loads.knot_times_s[i]);
  std::sort(cuts.begin(), cuts.end());
  std::vector<double> mid, len;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c)
    if (cuts[c + 1] - cuts[c] > 1e-12 * P) mid.push_back(0.5 * (cuts[c] + cuts[c + 1])), len.push_back(cuts[c + 1] - cuts[c]);
  const Eigen::Map<const Eigen::VectorXd> t(mid.data(), static_cast<Eigen::Index>(mid.size()));
  const Eigen::Map<const Eigen::VectorXd> w(len.data(), static_cast<Eigen::Index>(len.size()));
  const Loads at = loads_at(loads, t, switches);
  Loads out;
  out.period_s = P;
  out.times_s = Eigen::VectorXd::Zero(1);
  out.in_shadow.assign(1, 0);
  for (const LoadComponent& c : load_components()) out.*c.W = at.*c.W * w / P;
  return out;
}

Loads every_other_position(const Loads& loads) {
  const int S = loads.num_steps();
  if (S % 2 != 0 || S < 4) throw InvalidInput("every_other_position: need an even number >= 4 of positions");
  Loads out = loads;
  const int H = S / 2;
  auto half = [&](const Eigen::MatrixXd& m) {
    Eigen::MatrixXd h(m.rows(), H);
    for (int k = 0; k < H; ++k) h.col(k) = m.col(2 * k);
    return h;
  };
  out.times_s = half(loads.times_s.transpose()).transpose();
  for (const LoadComponent& c : load_components()) out.*c.W = half(loads.*c.W);
  if (loads.sampling_standard_error_W.cols() == S) out.sampling_standard_error_W = half(loads.sampling_standard_error_W);
  if (static_cast<int>(loads.in_shadow.size()) == S) {
    out.in_shadow.resize(H);
    for (int k = 0; k < H; ++k) out.in_shadow[k] = loads.in_shadow[2 * k];
  }
  return out;
}

}  // namespace thermodec
