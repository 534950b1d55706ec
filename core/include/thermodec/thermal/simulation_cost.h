#pragma once
//! What one simulation of a model costs, estimated from its settings before any ray is traced.
//!
//! Every knob of a model file has a range (docs/model-format.md), but valid values can still ask
//! for days of work: 10^7 rays per face side on a 10 000-face mesh, a million orbit positions, a
//! thousand thermal nodes in an orbit transient. The estimate counts the rays each stage traces,
//! the steps and the per-step cost of the thermal solver, and the memory of the tables that grow
//! with those knobs, so that a front end can say what a run will cost and refuse one beyond
//! SimulationCostLimits (the CLI does, unless `--force` is given; docs/model-format.md,
//! "Validation"). Counts are upper bounds of what the chain does (thermal/simulate_model.h),
//! computed in milliseconds: surface sides and their ray counts exactly, sunlit orbit positions
//! from the orbit geometry, the time grids of every refinement level.
#include <string>
#include <vector>

#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

//! The part of the chain a command runs: `viewfactors` traces the IR rays only.
enum class SimulationCostScope { view_factors, simulation };

//! Work per simulation step of the thermal solver, in units of one node-cubed operation: the
//! dense LU factorisations of a step (Newton, and the sensitivity dT(P)/dT(0) the periodicity
//! shooting propagates) cost ~N^3 units; the fixed cost of a step (assembly, interpolated loads,
//! small allocations) is worth kSolverStepOverhead units. One unit takes ~0.85 ns on one core of
//! the reference machine (42 us a step at 13 nodes, 0.83 ms at 100, 23 ms at 300).
constexpr double kSolverStepOverhead = 4e4;

struct SimulationCost {
  SimulationCostScope scope = SimulationCostScope::simulation;
  int sides = 0;                //!< radiating surface sides (fronts + backs of two-sided faces)
  int nodes = 0;                //!< thermal nodes N
  int load_positions = 0;       //!< orbit positions where loads are ray traced (1 for a fixed sun)
  int shadow_passes = 0;        //!< lit positions with a new sun direction in body axes (shadow traces)
  //! A side's shadow samples traced at each pass are its count / this (rounded up): D for a
  //! steady orbit's passes (shadow_pass_division), 1 otherwise.
  int shadow_division = 1;
  double ir_rays = 0.0;         //!< IR view-factor rays: every side's count (per-node minimums, boosts)
  //! Shadow rays, at most: every side's full count at each shadow pass (the pilot rays stop
  //! early on fully lit or fully shadowed sides).
  double sun_rays = 0.0;
  double earth_rays = 0.0;      //!< Earth rays, at most: every side's full count, traced once a run
  //! Sun-pointing and inertial attitudes: escaping hemisphere rays tested against the Earth's
  //! cone at every position (a few ns each, no tracing).
  double earth_ray_tests = 0.0;
  //! Thermal solver time steps, at most: every refinement level of the orbit transient
  //! (OrbitTimeSettings::max_levels), each over min(orbits, 3) orbits (the shooting Newton
  //! converges in 2 or 3; analysis.orbits only bounds a run that does not); 0 for steady.
  double solver_steps = 0.0;
  //! solver_steps x (N^3 + kSolverStepOverhead); steady: 20 Newton iterations x N^3.
  double solver_work = 0.0;
  // Memory [bytes] of what grows with the knobs (mesh, scene and view-factor rows aside):
  double sobol_table_bytes = 0.0;   //!< 16 bytes x the most rays any side draws (one shared table)
  double side_table_bytes = 0.0;    //!< per side and position loads, sun sample points, escaping rays, Gebhart rows
  double solver_bytes = 0.0;        //!< temperatures and loads on the finest time grid
  double node_matrix_bytes = 0.0;   //!< N x N couplings, Jacobians, sensitivities
  //! The view-factor rows, at most: 12 bytes (column index and value) per distinct side a
  //! side's rays hit, i.e. sum over sides of min(rays, sides). Geometry decides how far below
  //! it they stay (a flat plate's rays all escape; the generated satellite at 100k faces and
  //! 4000 rays per face peaks at 6 GiB against a bound of 9.6), so it is shown, not guarded.
  double view_factor_bytes_max = 0.0;

  double rays() const { return ir_rays + sun_rays + earth_rays; }
  double memory_bytes() const { return sobol_table_bytes + side_table_bytes + solver_bytes + node_matrix_bytes; }
  //! One line, e.g. "3.1e+07 rays (IR 6.9e+06, sun 2.1e+07, Earth 3.5e+06); 4.6e+04 solver
  //! steps x 13 nodes (work 1.9e+09); memory 45 MB + view-factor rows up to 40 MB".
  std::string summary() const;
};

//! Estimates one simulation of `model` with `settings` (the same settings simulate_model takes:
//! load sample counts, solver grids, steps_per_orbit override). `scope` view_factors counts the
//! IR rays and their table only. Costs O(sides + load positions).
//! \throw InvalidInput where the simulation itself would (a face naming a missing node or
//! material, a sampling boost outside [1, 10000], bad orbit elements).
SimulationCost simulation_cost(const ThermalModel& model, const ModelSimulationSettings& settings = {},
                               SimulationCostScope scope = SimulationCostScope::simulation);

//! `cost` with noise-targeted sampling's two runs (thermal/simulate_model.h): the run at the
//! model's counts that estimates the noise, then the boosted one, whose extra samples of each
//! kind are at most `max_extra` x the model's total and at most `max_extra_samples` per-side
//! samples in all. A sun sample is traced at every shadow pass, once per `shadow_division`
//! passes on a steady orbit (as the model's own samples are), so its cap counts that often.
SimulationCost noise_targeted_cost(SimulationCost cost, double max_extra, double max_extra_samples);

//! Limits above which a run is refused (docs/model-format.md, "Validation"). The defaults leave
//! the sample satellite 200x below the ray limit, and a 100 000-face model at default settings
//! (4000 IR rays per face, 72 positions) 3x below it even when every face is two-sided.
struct SimulationCostLimits {
  double max_rays = 1e10;            //!< ~25 min of tracing on 2 cores (7 M rays/s)
  double max_solver_work = 2e12;     //!< ~30 min of thermal solve (0.85 ns a unit)
  double max_memory_bytes = 16.0 * (1ull << 30);  //!< 16 GiB
};

//! Empty if `cost` is within `limits`; otherwise one line naming the estimate, the limit and the
//! knobs of `model` / `settings` that drive it, e.g. "6.5e+11 rays traced (limit 1e+10), mostly
//! shadow rays: analysis.steps_per_orbit = 1000000 ...".
std::string simulation_cost_excess(const SimulationCost& cost, const ThermalModel& model,
                                   const ModelSimulationSettings& settings = {},
                                   const SimulationCostLimits& limits = {});

//! What every front end checks before a simulation's expensive work (the CLI's simulating
//! commands, the Python module, MeshLab's filters and so FreeCAD's workbench): the estimate of
//! one simulation of `model`, and of it in each of `cases`, with noise-targeted sampling's two
//! runs and extra samples when `noise_max_extra` > 0 (noise_targeted_cost). `excess` names the
//! first estimate over SimulationCostLimits, or whose memory with the view-factor rows' upper
//! bound is beyond this machine's, and the setting that drives it; empty when all are within.
struct SimulationCostCheck {
  //! Per case: "estimated cost[ (case NAME)][ with noise-targeted sampling]: " + summary().
  std::vector<std::string> estimates;
  //! Why the first estimate over a limit is (simulation_cost_excess or this machine's memory),
  //! empty if none is; `excess_case` = " (case NAME)" for it when there are cases.
  std::string excess, excess_case;
};
SimulationCostCheck check_simulation_cost(const ThermalModel& model, const ModelSimulationSettings& settings,
                                          const std::vector<LoadCase>& cases = {},
                                          SimulationCostScope scope = SimulationCostScope::simulation,
                                          double noise_max_extra = 0.0, double noise_max_samples = 0.0);

//! check_simulation_cost for simulate_as_front_end's run: noise targeting's extras counted when
//! it is on and the model carries no boosts of its own (apply_noise_targeting's rule).
SimulationCostCheck check_front_end_simulation_cost(const ThermalModel& model, const ModelSimulationSettings& settings,
                                                    const NoiseTargeting& targeting = {});

//! Throws InvalidInput "estimated cost[ (case NAME)] over the limit: WHY; lower that setting, or
//! HOW_TO_FORCE ..." when `check` has an excess and `force` is false (e.g. how_to_force = "pass
//! --force to run anyway").
void refuse_costly_run(const SimulationCostCheck& check, bool force, const std::string& how_to_force);

}  // namespace thermodec
