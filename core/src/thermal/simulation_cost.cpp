// Cost of one simulation from the model's settings. The counts follow what the stages do
// (radiation/face_view_factors.cpp, environment/external_loads.cpp, thermal/orbit_transient.cpp);
// where a stage decides at run time (pilot rays, refinement levels), the estimate takes the
// larger branch, so that a refusal never rests on an optimistic guess.
#include "thermodec/thermal/simulation_cost.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "thermodec/common/errors.h"
#include "thermodec/common/physical_memory.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec {
namespace {

std::string sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  return buf;
}

std::string bytes_text(double b) {
  char buf[32];
  if (b >= double(1ull << 30)) std::snprintf(buf, sizeof buf, "%.1f GiB", b / double(1ull << 30));
  else std::snprintf(buf, sizeof buf, "%.0f MiB", std::ceil(b / double(1ull << 20)));
  return buf;
}

double sum(const Eigen::VectorXi& v) { return v.cast<double>().sum(); }
int max_of(const Eigen::VectorXi& v) { return v.size() ? v.maxCoeff() : 0; }

int load_positions(const ThermalModel& model, const ModelSimulationSettings& settings) {
  if (model.environment.type != EnvironmentType::orbit) return 1;
  return settings.loads.steps_per_orbit > 0 ? settings.loads.steps_per_orbit : model.analysis.steps_per_orbit;
}

// Shadow passes of the direct sun and whether the Earth stays put in body axes, counted as the
// loads count them (orbit.h).
struct OrbitPasses {
  int shadow = 0;
  bool earth_fixed = true;
};

OrbitPasses orbit_passes(const ThermalModel& model, int positions) {
  OrbitPasses out;
  const Environment& env = model.environment;
  if (env.type != EnvironmentType::orbit) {
    out.shadow = env.solar_flux_W_per_m2 > 0.0 ? 1 : 0;
    return out;
  }
  const double period_s = orbit_period_s(env);
  std::vector<OrbitState> states;
  for (int k = 0; k < positions; ++k) states.push_back(orbit_state(env, period_s * k / positions));
  out.shadow = sun_passes(states);
  out.earth_fixed = earth_fixed_in_body(states);
  return out;
}

// Time steps of the orbit transient: level l of orbit_transient's grids has (substeps x S + the
// eclipse cuts) x 2^l steps; every level runs the periodic solve over its orbits.
double orbit_solver_steps(const ThermalModel& model, const ModelSimulationSettings& settings, int positions,
                          double& finest_grid_steps) {
  const OrbitTimeSettings& time = settings.solver.time;
  const int max_orbits = settings.solver.transient.max_orbits >= 1 ? settings.solver.transient.max_orbits
                                                                    : model.analysis.orbits;
  const double orbits = std::min(max_orbits, 3);
  const double coarsest = double(std::max(1, time.substeps)) * positions + 2.0;  // + eclipse entry and exit
  const int levels = std::clamp(time.max_levels, 1, 40);
  finest_grid_steps = coarsest * std::exp2(levels - 1);
  return orbits * coarsest * (std::exp2(levels) - 1.0);
}

void add_loads(SimulationCost& c, const ThermalModel& model, const ModelSimulationSettings& settings,
               const SurfaceSides& sides) {
  const ExternalLoadSettings& ls = settings.loads;
  const Eigen::VectorXi sun = rays_per_side_of_node(sides, ls.sun_rays_per_face, ls.sun_min_rays_per_node, sides.load_boost);
  const Eigen::VectorXi earth =
      rays_per_side_of_node(sides, ls.earth_rays_per_face, ls.earth_min_rays_per_node, sides.load_boost);
  const OrbitPasses passes = orbit_passes(model, c.load_positions);
  c.shadow_passes = passes.shadow;
  // A steady orbit analysis draws 1/D of the points at each pass (external_loads.h).
  c.shadow_division = shadow_pass_division(model, ls, passes.shadow);
  const Eigen::VectorXi sun_per_pass = shadow_rays_per_pass(sun, c.shadow_division);
  const int most_per_pass = sides.size() > 0 ? sun_per_pass.maxCoeff() : 0;
  c.sun_rays = double(passes.shadow) *
               std::max(sum(sun_per_pass), double(std::min(ls.sun_pilot_rays, most_per_pass)) * sides.size());
  const bool orbit = model.environment.type == EnvironmentType::orbit;
  double escaping_bytes = 0.0;
  if (orbit && passes.earth_fixed) {
    // Every side draws its pilot; a side whose Earth view may be blocked draws all its rays.
    c.earth_rays = std::max(sum(earth), double(ls.earth_pilot_rays) * sides.size());
  } else if (orbit) {
    c.earth_rays = sum(earth);
    c.earth_ray_tests = c.earth_rays * c.load_positions;
    escaping_bytes = 12.0 * c.earth_rays;  // float directions of the escaping rays
  }
  const int most = std::max({max_of(sun), max_of(earth), ls.sun_pilot_rays, ls.earth_pilot_rays, ls.earth_rays_per_face});
  c.sobol_table_bytes = std::max(c.sobol_table_bytes, 16.0 * most);
  // Per side and position: direct and albedo incident power, reflected share, sunlit fraction
  // and Earth lighting (doubles and a float); per side: its sun sample points (3 floats each);
  // the IR and solar Gebhart rows (#nodes + 2 doubles each).
  c.side_table_bytes = 36.0 * sides.size() * c.load_positions + 12.0 * sum(sun) + escaping_bytes +
                       2.0 * 8.0 * sides.size() * (c.nodes + 2.0);
}

void add_solver(SimulationCost& c, const ThermalModel& model, const ModelSimulationSettings& settings) {
  const double n = c.nodes, n3 = n * n * n;
  const double loads_bytes = 6.0 * 8.0 * n * c.load_positions;  // solar, albedo, IR, reflected, error, total
  const bool transient = model.analysis.type == AnalysisType::transient_orbit &&
                         model.environment.type == EnvironmentType::orbit && c.load_positions >= 2;
  if (transient) {
    double finest = 0.0;
    c.solver_steps = orbit_solver_steps(model, settings, c.load_positions, finest);
    c.solver_work = c.solver_steps * (n3 + kSolverStepOverhead);
    // States, interpolated loads and temperatures of the finest grid, one double per node each.
    c.solver_bytes = 3.0 * 8.0 * n * finest + loads_bytes;
  } else {
    c.solver_work = 20.0 * n3;
    c.solver_bytes = loads_bytes;
  }
}

}  // namespace

SimulationCost simulation_cost(const ThermalModel& model, const ModelSimulationSettings& settings,
                               SimulationCostScope scope) {
  SimulationCost c;
  c.scope = scope;
  const SurfaceSides sides = surface_sides(model);
  c.sides = sides.size();
  c.nodes = static_cast<int>(model.nodes.size());
  const Eigen::VectorXi ir = side_ray_counts(sides, model.radiation);
  c.ir_rays = sum(ir);
  c.sobol_table_bytes = 16.0 * max_of(ir);
  for (int s = 0; s < ir.size(); ++s) c.view_factor_bytes_max += 12.0 * std::min<double>(ir[s], c.sides);
  // Node couplings, their standard errors, view factors (radiation stage); the network, Jacobians,
  // sensitivity and its LU (thermal stage): about a dozen dense N x N matrices.
  c.node_matrix_bytes = 12.0 * 8.0 * double(c.nodes) * c.nodes;
  if (scope == SimulationCostScope::view_factors) {
    c.node_matrix_bytes /= 2.0;
    c.side_table_bytes = 8.0 * sides.size() * (c.nodes + 1.0);  // IR Gebhart rows
    return c;
  }
  c.load_positions = load_positions(model, settings);
  add_loads(c, model, settings, sides);
  add_solver(c, model, settings);
  return c;
}

std::string SimulationCost::summary() const {
  std::string s = sci(rays()) + " rays (IR " + sci(ir_rays);
  if (scope == SimulationCostScope::simulation) {
    s += ", sun " + sci(sun_rays) + ", Earth " + sci(earth_rays) + ")";
    if (earth_ray_tests > 0.0) s += " + " + sci(earth_ray_tests) + " Earth cone tests";
    s += "; ";
    s += solver_steps > 0.0 ? sci(solver_steps) + " solver steps" : std::string("steady solve");
    s += " x " + std::to_string(nodes) + " nodes (work " + sci(solver_work) + ")";
  } else {
    s += ")";
  }
  return s + "; memory " + bytes_text(memory_bytes()) + " + view-factor rows up to " + bytes_text(view_factor_bytes_max);
}

SimulationCost noise_targeted_cost(SimulationCost c, double max_extra, double max_extra_samples) {
  const auto boosted = [&](double base, double passes) {
    return 2.0 * base + std::min(max_extra * base, max_extra_samples * passes);
  };
  c.ir_rays = boosted(c.ir_rays, 1.0);
  c.sun_rays = boosted(c.sun_rays, double(std::max(1, c.shadow_passes)) / double(std::max(1, c.shadow_division)));
  c.earth_ray_tests *= 2.0 + max_extra;
  c.earth_rays = boosted(c.earth_rays, 1.0);
  return c;
}

std::string simulation_cost_excess(const SimulationCost& c, const ThermalModel& model,
                                   const ModelSimulationSettings& settings, const SimulationCostLimits& limits) {
  const RadiationSettings& r = model.radiation;
  const ExternalLoadSettings& ls = settings.loads;
  const std::string positions = "analysis.steps_per_orbit = " + std::to_string(c.load_positions) + " load positions";
  if (c.rays() > limits.max_rays) {
    std::string why;
    if (c.ir_rays >= c.sun_rays && c.ir_rays >= c.earth_rays) {
      why = "mostly IR view-factor rays: radiation.rays_per_face = " + std::to_string(r.rays_per_face) + " over " +
            std::to_string(c.sides) + " face sides";
      if (c.ir_rays > 1.5 * double(r.rays_per_face) * c.sides)
        why += ", raised by radiation.min_rays_per_node = " + std::to_string(r.min_rays_per_node) +
               " and the nodes' sampling_boost.ir";
    } else if (c.sun_rays >= c.earth_rays) {
      why = "mostly shadow rays: " + std::to_string(c.shadow_passes) + " sunlit passes (" + positions + ") x " +
            sci(c.sun_rays / std::max(1, c.shadow_passes)) + " sun samples a pass (" +
            std::to_string(ls.sun_rays_per_face) + " per face side, at least " + std::to_string(ls.sun_min_rays_per_node) +
            " per node, times sampling_boost.loads)";
    } else {
      why = "mostly Earth rays: " + std::to_string(ls.earth_rays_per_face) + " per face side over " +
            std::to_string(c.sides) + " sides (at least " + std::to_string(ls.earth_min_rays_per_node) +
            " per node, times sampling_boost.loads)";
    }
    return sci(c.rays()) + " rays to trace (limit " + sci(limits.max_rays) + "), " + why;
  }
  if (c.solver_work > limits.max_solver_work) {
    return "thermal solver work " + sci(c.solver_work) + " (limit " + sci(limits.max_solver_work) + "): " +
           std::to_string(c.nodes) + " nodes (the work grows as nodes^3) x up to " + sci(c.solver_steps) +
           " time steps (" + positions + ", up to " + std::to_string(settings.solver.time.max_levels) +
           " grid refinements, " + std::to_string(std::min(model.analysis.orbits, 3)) + " orbits)";
  }
  if (c.memory_bytes() > limits.max_memory_bytes) {
    std::string why;
    const double parts[] = {c.sobol_table_bytes, c.side_table_bytes, c.solver_bytes, c.node_matrix_bytes};
    const int worst = static_cast<int>(std::max_element(parts, parts + 4) - parts);
    if (worst == 0)
      why = "mostly the sample table of the side with the most rays (" + sci(c.sobol_table_bytes / 16.0) +
            " rays: radiation.rays_per_face, radiation.min_rays_per_node, sampling_boost)";
    else if (worst == 1)
      why = "mostly per-side tables: " + std::to_string(c.sides) + " face sides x " + positions;
    else if (worst == 2)
      why = "mostly the solver's time grids: " + std::to_string(c.nodes) + " nodes x " + positions +
            " x up to " + std::to_string(1 << std::clamp(settings.solver.time.max_levels - 1, 0, 30)) + " refinements";
    else
      why = "mostly node-to-node matrices: " + std::to_string(c.nodes) + " nodes (memory grows as nodes^2)";
    return "memory " + bytes_text(c.memory_bytes()) + " (limit " + bytes_text(limits.max_memory_bytes) + "), " + why;
  }
  return {};
}

namespace {
// The view-factor rows are an upper bound that geometry decides how far below it they stay;
// beyond the machine's memory, a run may be killed by the system after hours of work.
std::string memory_excess(const SimulationCost& c) {
  const double machine = double(physical_memory_bytes());
  const double need = c.memory_bytes() + c.view_factor_bytes_max;
  if (machine <= 0.0 || need <= machine) return {};
  return "memory up to " + bytes_text(need) + " (view-factor rows up to " + bytes_text(c.view_factor_bytes_max) +
         ": radiation.rays_per_face over " + std::to_string(c.sides) + " face sides) is more than this machine's " +
         bytes_text(machine);
}
}  // namespace

SimulationCostCheck check_simulation_cost(const ThermalModel& model, const ModelSimulationSettings& settings,
                                          const std::vector<LoadCase>& cases, SimulationCostScope scope,
                                          double noise_max_extra, double noise_max_samples) {
  std::vector<LoadCase> all{own_case(model)};
  all.insert(all.end(), cases.begin(), cases.end());
  SimulationCostCheck out;
  for (const LoadCase& c : all) {
    const ThermalModel m = cases.empty() ? model : with_case(model, c);
    SimulationCost cost = simulation_cost(m, settings, scope);
    if (noise_max_extra > 0.0) cost = noise_targeted_cost(cost, noise_max_extra, noise_max_samples);
    const std::string which = cases.empty() ? std::string() : " (case " + c.name + ")";
    out.estimates.push_back("estimated cost" + which + (noise_max_extra > 0.0 ? " with noise-targeted sampling" : "") +
                            ": " + cost.summary());
    if (!out.excess.empty()) continue;
    std::string excess = simulation_cost_excess(cost, m, settings);
    if (excess.empty()) excess = memory_excess(cost);
    if (!excess.empty()) out.excess = excess, out.excess_case = which;
  }
  return out;
}

SimulationCostCheck check_front_end_simulation_cost(const ThermalModel& model, const ModelSimulationSettings& settings,
                                                    const NoiseTargeting& targeting) {
  const bool noise = targeting.target_K > 0.0 && !has_sampling_boosts(model);
  return check_simulation_cost(model, settings, {}, SimulationCostScope::simulation, noise ? targeting.budget : 0.0,
                               noise ? targeting.max_samples : 0.0);
}

void refuse_costly_run(const SimulationCostCheck& check, bool force, const std::string& how_to_force) {
  if (check.excess.empty() || force) return;
  throw InvalidInput("estimated cost" + check.excess_case + " over the limit: " + check.excess +
                     "; lower that setting, or " + how_to_force +
                     " (docs/model-format.md, \"Validation\")");
}

}  // namespace thermodec
