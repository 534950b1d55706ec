// Orbit-periodic transient: theta-method time stepping and shooting-Newton on the initial
// state (Aprille & Trick, "Steady-state analysis of nonlinear circuits with periodic inputs",
// Proc. IEEE 1972). Plain repetition of orbits converges with the slowest node time constant
// (hours for a heavy node, i.e. tens of orbits for 1e-3 K); shooting needs 2-3 orbits because
// the orbit map is only weakly nonlinear.
#include "thermodec/thermal/transient.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "heat_balance.h"
#include "thermodec/common/errors.h"

namespace thermodec {
namespace detail {
Eigen::VectorXd linearised_guess(const HeatBalance& hb, const Eigen::VectorXd& external_W);
std::vector<std::string> free_names(const HeatBalance& hb);
}  // namespace detail

double OrbitEnergy::relative_imbalance() const {
  const double scale = std::max(std::abs(absorbed_J), 1e-300);
  return std::abs(absorbed_J - emitted_J - to_boundary_J - stored_J) / scale;
}

namespace {

struct OrbitRun {
  Eigen::MatrixXd x;             // free x (S + 1): states at t_0 .. t_S
  Eigen::MatrixXd sensitivity;   // d x_S / d x_0
  OrbitEnergy energy;
  Eigen::MatrixXd heater_W;      // N x S, column k: heater power over the step ending at t_k (empty: no heaters)
};

// Thermostats. A heater's state at the start of a step: from its node's temperature there
// (below on_K: on; above off_K: off; else unchanged; this only acts on a start outside the
// band). Within the step, a node that crosses the band edge its heater's state heads for is
// located by linear interpolation of T between the step's ends: the heater is on for its share
// of the step (power x share: the step's energy to first order) and switched for the next one.
// Without that location the orbit map would jump with the step a switch falls in, and the
// shooting could cycle between two neighbouring steps instead of converging. A switch pins the
// node's temperature at that instant to the band edge whatever the orbit's start: the node's
// row of the sensitivity d x / d x_0 is zeroed there (the first-order effect of an event; the
// other nodes' dependence through the switch time is neglected).
bool locate_heater_switches(const detail::HeatBalance& hb, const Eigen::VectorXd& T0, const Eigen::VectorXd& T1,
                            std::vector<char>& on, Eigen::VectorXd& heater_W, std::vector<int>& switched) {
  switched.clear();
  for (std::size_t h = 0; h < hb.net.heaters.size(); ++h) {
    const NetworkHeater& heater = hb.net.heaters[h];
    const int i = heater.node;
    const double edge = on[h] ? heater.thermostat.off_K : heater.thermostat.on_K;
    if (on[h] ? !(T1[i] > edge) : !(T1[i] < edge)) continue;
    const double before = std::clamp((edge - T0[i]) / (T1[i] - T0[i]), 0.0, 1.0);  // share before the crossing
    heater_W[i] += heater.thermostat.power_W * ((on[h] ? before : 1.0 - before) - (on[h] ? 1.0 : 0.0));
    on[h] = !on[h];
    switched.push_back(i);
  }
  return !switched.empty();
}

void switch_heaters(const detail::HeatBalance& hb, const Eigen::VectorXd& T, std::vector<char>& on,
                    const std::vector<int>& free_index, Eigen::MatrixXd& sensitivity, Eigen::VectorXd& E,
                    Eigen::VectorXd& heater_W) {
  heater_W.setZero();
  for (std::size_t h = 0; h < hb.net.heaters.size(); ++h) {
    const NetworkHeater& heater = hb.net.heaters[h];
    const int i = heater.node;
    const char was = on[h];
    if (T[i] < heater.thermostat.on_K) on[h] = 1;
    else if (T[i] > heater.thermostat.off_K) on[h] = 0;
    if (on[h] != was && free_index[i] >= 0) sensitivity.row(free_index[i]).setZero();
    if (on[h]) heater_W[i] += heater.thermostat.power_W;
  }
  E += heater_W;
}

OrbitRun run_orbit(const detail::HeatBalance& hb, const Eigen::MatrixXd& loads, const Eigen::VectorXd& dts,
                   const Eigen::VectorXd& theta, const Eigen::VectorXd& x0, const NewtonSettings& newton,
                   const std::vector<std::string>& names, std::vector<char>& heater_on) {
  const int m = static_cast<int>(x0.size());
  const int S = static_cast<int>(loads.cols());
  Eigen::VectorXd c_dt(m);
  const Eigen::VectorXd one_minus_theta = Eigen::VectorXd::Ones(m) - theta;

  OrbitRun run;
  run.x.resize(m, S + 1);
  run.x.col(0) = x0;
  run.sensitivity = Eigen::MatrixXd::Identity(m, m);
  Eigen::VectorXd T_prev = hb.full(x0);
  Eigen::VectorXd R_prev = hb.restrict(hb.residual(T_prev, loads.col(0)));
  Eigen::MatrixXd J_prev = hb.restrict(hb.jacobian(T_prev));
  auto free_sum = [&](const Eigen::VectorXd& v_full, const Eigen::VectorXd& w) {
    return hb.restrict(v_full).dot(w);
  };
  Eigen::VectorXd ext_free_prev = hb.restrict(Eigen::VectorXd(hb.net.power_W + loads.col(0)));
  Eigen::VectorXd space_prev = hb.to_space_W(T_prev), fixed_prev = hb.to_fixed_W(T_prev);
  const bool heaters = !hb.net.heaters.empty();
  std::vector<int> free_index(hb.net.num_nodes(), -1);
  for (std::size_t a = 0; a < hb.free_nodes.size(); ++a) free_index[hb.free_nodes[a]] = static_cast<int>(a);
  Eigen::VectorXd heat(heaters ? hb.net.num_nodes() : 0);
  if (heaters) run.heater_W = Eigen::MatrixXd::Zero(hb.net.num_nodes(), S);
  std::vector<int> switched;

  for (int k = 0; k < S; ++k) {
    const double dt = dts[k];
    for (int a = 0; a < m; ++a) c_dt[a] = hb.net.capacitance_J_per_K[hb.free_nodes[a]] / dt;
    Eigen::VectorXd E = loads.col((k + 1) % S);
    if (heaters) {
      switch_heaters(hb, hb.full(run.x.col(k)), heater_on, free_index, run.sensitivity, E, heat);
      run.heater_W.col((k + 1) % S) = heat;
    }
    const Eigen::VectorXd xk = run.x.col(k);
    std::ostringstream what;
    what << "transient step " << k + 1 << "/" << S;
    auto solve_step = [&]() {
      Eigen::VectorXd x = xk;
      detail::newton_solve(
          x,
          [&](const Eigen::VectorXd& xf, Eigen::VectorXd& G, Eigen::MatrixXd* J) {
            const Eigen::VectorXd T = hb.full(xf);
            const Eigen::VectorXd R = hb.restrict(hb.residual(T, E));
            G = c_dt.cwiseProduct(xf - xk) - theta.cwiseProduct(R) - one_minus_theta.cwiseProduct(R_prev);
            if (J) {
              *J = -(theta.asDiagonal() * hb.restrict(hb.jacobian(T)));
              J->diagonal() += c_dt;
            }
          },
          newton, what.str(), names);
      return x;
    };
    Eigen::VectorXd x = solve_step();
    switched.clear();
    if (heaters && locate_heater_switches(hb, hb.full(xk), hb.full(x), heater_on, heat, switched)) {
      E = loads.col((k + 1) % S) + heat;  // the heaters' power over this step, shares included
      run.heater_W.col((k + 1) % S) = heat;
      x = solve_step();
    }
    run.x.col(k + 1) = x;
    const Eigen::VectorXd T = hb.full(x);
    const Eigen::MatrixXd J_full = hb.restrict(hb.jacobian(T));
    Eigen::MatrixXd A = -(theta.asDiagonal() * J_full);
    A.diagonal() += c_dt;
    Eigen::MatrixXd B = one_minus_theta.asDiagonal() * J_prev;
    B.diagonal() += c_dt;
    run.sensitivity = Eigen::PartialPivLU<Eigen::MatrixXd>(A).solve(B * run.sensitivity);
    for (const int i : switched)
      if (free_index[i] >= 0) run.sensitivity.row(free_index[i]).setZero();

    // Energy with the scheme's own quadrature, so the discrete balance closes exactly.
    const Eigen::VectorXd ext_free = hb.restrict(Eigen::VectorXd(hb.net.power_W + E));
    const Eigen::VectorXd space = hb.to_space_W(T), fixed = hb.to_fixed_W(T);
    run.energy.absorbed_J += dt * (theta.dot(ext_free) + one_minus_theta.dot(ext_free_prev));
    run.energy.emitted_J += dt * (free_sum(space, theta) + free_sum(space_prev, one_minus_theta));
    run.energy.to_boundary_J += dt * (free_sum(fixed, theta) + free_sum(fixed_prev, one_minus_theta));

    R_prev = hb.restrict(hb.residual(T, E));
    J_prev = J_full;
    ext_free_prev = ext_free;
    space_prev = space;
    fixed_prev = fixed;
  }
  for (int a = 0; a < m; ++a)
    run.energy.stored_J += hb.net.capacitance_J_per_K[hb.free_nodes[a]] * (run.x(a, S) - run.x(a, 0));
  return run;
}

}  // namespace

PeriodicTransient periodic_transient(const ThermalNetwork& network, const Eigen::MatrixXd& loads,
                                     double period_s, const TransientSettings& s) {
  if (loads.cols() < 2) throw InvalidInput("transient: need at least 2 time steps per orbit");
  if (!(period_s > 0.0)) throw InvalidInput("transient: orbit period must be > 0 s");
  const int S = static_cast<int>(loads.cols());
  return periodic_transient_on_grid(network, loads, Eigen::VectorXd::LinSpaced(S, 0.0, period_s / S * (S - 1)),
                                    period_s, s);
}

PeriodicTransient periodic_transient_on_grid(const ThermalNetwork& network, const Eigen::MatrixXd& loads,
                                             const Eigen::VectorXd& times_s, double period_s,
                                             const TransientSettings& s) {
  validate_network(network);
  detail::validate_loads(network, loads, "transient");
  if (loads.cols() < 2) throw InvalidInput("transient: need at least 2 time steps per orbit");
  if (!(period_s > 0.0)) throw InvalidInput("transient: orbit period must be > 0 s");
  if (!(s.theta >= 0.5 && s.theta <= 1.0)) throw InvalidInput("transient: theta must be in [0.5, 1]");
  if (!(s.periodicity_tolerance_K > 0.0)) throw InvalidInput("transient: periodicity tolerance must be > 0 K");
  if (s.max_orbits < 1) throw InvalidInput("transient: max_orbits must be >= 1");
  if (times_s.size() != loads.cols() || times_s[0] != 0.0)
    throw InvalidInput("transient: need one time per load column, the first at 0 s");
  for (int k = 0; k < times_s.size(); ++k)
    if (!(times_s[k] < (k + 1 < times_s.size() ? times_s[k + 1] : period_s)))
      throw InvalidInput("transient: times must increase and stay below the orbit period");
  detail::require_paths_to_sinks(network, "transient");

  const detail::HeatBalance hb(network);
  const int m = static_cast<int>(hb.free_nodes.size());
  const int S = static_cast<int>(loads.cols());
  Eigen::VectorXd dts(S);
  for (int k = 0; k < S; ++k) dts[k] = (k + 1 < S ? times_s[k + 1] : period_s) - times_s[k];
  const auto names = detail::free_names(hb);
  Eigen::VectorXd theta(m);
  for (int a = 0; a < m; ++a)
    theta[a] = network.capacitance_J_per_K[hb.free_nodes[a]] > 0.0 ? s.theta : 1.0;

  // Start from the steady state of the mean loads: exact for constant loads.
  const Eigen::VectorXd mean_loads = loads * dts / period_s;
  Eigen::VectorXd x0;
  {
    Eigen::VectorXd guess = detail::linearised_guess(hb, mean_loads);
    detail::newton_solve(
        guess,
        [&](const Eigen::VectorXd& xf, Eigen::VectorXd& G, Eigen::MatrixXd* J) {
          const Eigen::VectorXd T = hb.full(xf);
          G = hb.restrict(hb.residual(T, mean_loads));
          if (J) *J = hb.restrict(hb.jacobian(T));
        },
        s.newton, "transient (orbit-mean steady state)", names);
    x0 = guess;
  }

  PeriodicTransient out;
  out.times_s = times_s;
  // Heaters start on where the start guess is below the band.
  std::vector<char> heater_on;
  {
    const Eigen::VectorXd T0 = hb.full(x0);
    for (const NetworkHeater& h : network.heaters) heater_on.push_back(T0[h.node] < h.thermostat.on_K);
  }
  for (int orbit = 1; orbit <= s.max_orbits; ++orbit) {
    const std::vector<char> heater_start = heater_on;
    const OrbitRun run = run_orbit(hb, loads, dts, theta, x0, s.newton, names, heater_on);
    const Eigen::VectorXd gap = run.x.col(S) - x0;
    // A heater that ends the orbit in another state than it began is not periodic either.
    const double residual = m ? gap.cwiseAbs().maxCoeff() : 0.0;
    const bool periodic = residual <= s.periodicity_tolerance_K && heater_on == heater_start;
    if (s.on_orbit) s.on_orbit(orbit, residual);
    out.orbits = orbit;
    out.periodicity_residual_K = residual;
    if (periodic || orbit == s.max_orbits) {
      out.temperature_K.resize(network.num_nodes(), S);
      for (int k = 0; k < S; ++k) out.temperature_K.col(k) = hb.full(run.x.col(k));
      out.energy = run.energy;
      out.heater_power_W = run.heater_W;
      if (!periodic) {
        std::ostringstream msg;
        msg << "transient: not orbit-periodic within " << s.periodicity_tolerance_K << " K after " << orbit
            << " orbits (max |T(P) - T(0)| = " << residual << " K"
            << (heater_on == heater_start ? "" : "; a thermostat heater ends the orbit in another state than it began")
            << "); raise analysis.orbits";
        throw SolverError(msg.str());
      }
      return out;
    }
    // Shooting-Newton update; fall back to plain repetition if it would leave T > 0.
    const Eigen::MatrixXd I_minus_M = Eigen::MatrixXd::Identity(m, m) - run.sensitivity;
    Eigen::VectorXd next = x0 + Eigen::PartialPivLU<Eigen::MatrixXd>(I_minus_M).solve(gap);
    if (!next.allFinite() || (next.array() <= 0.0).any()) next = run.x.col(S);
    x0 = next;
  }
  return out;  // unreachable
}

}  // namespace thermodec
