#pragma once
//! The whole reference simulation of a model, as `thermodec simulate` runs it: radiative
//! couplings (radiation stage), external loads (environment stage), then the thermal solve
//! (thermal/simulate.h); plus the Monte Carlo noise floor of that chain.
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "thermodec/environment/external_loads.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/thermal/simulate.h"

namespace thermodec {

struct ModelSimulationSettings {
  ExternalLoadSettings loads;    //!< loads.seed is replaced by the model's radiation seed
  SimulationSettings solver;
  //! IR and solar-reflection view-factor rows with planar control variates (docs/radiation.md,
  //! "Planar control variates"); a reduction turns it off (its trials count rays one by one).
  bool planar_strata = true;
  //! Optional progress messages (stage names with elapsed seconds).
  std::function<void(const std::string&)> progress;
};

//! Runs the chain with model.radiation (rays, seed) for couplings and load sampling:
//! couplings from face_view_factors, then chain_loads and solve_chain.
//! \throw InvalidInput / SolverError from the stages.
//! `couplings_out`, if given, receives the node couplings the solve used.
SimulationResult simulate_model(const ThermalModel& model, const ModelSimulationSettings& settings = {},
                                NodeCouplings* couplings_out = nullptr);

//! The load settings of a simulation of `model`: settings.loads with the model's Monte Carlo
//! seed (model.radiation.seed) and, with settings.planar_strata, the shadow control variates.
//! The one place a simulation's load sampling takes its seed.
ExternalLoadSettings chain_load_settings(const ThermalModel& model, const ModelSimulationSettings& settings);

//! The chain's external loads, given its ray scene and face view factors (which also carry
//! the solar reflections): sampled with chain_load_settings. `record`, if given, receives the
//! samples for later incremental re-sampling (environment/external_loads.h).
Loads chain_loads(const ThermalModel& model, const RayScene& scene, const FaceViewFactors& view_factors,
                  const ModelSimulationSettings& settings, LoadSamples* record = nullptr);

//! The chain's last step: the thermal solve of `model` with these couplings and loads
//! (progress: one line per transient orbit).
SimulationResult solve_chain(const ThermalModel& model, const NodeCouplings& couplings, const Loads& loads,
                             const ModelSimulationSettings& settings);

//! Noise-targeted sampling (docs/thermal.md, "Noise-targeted sampling"): simulates the model
//! once at its own sample counts, estimates each node's temperature standard error from the
//! couplings' (IR rays) and from the loads' (sun and Earth samples), separately
//! (thermal/temperature_noise.h), and picks Node::sampling_boost.ir / .loads for the nodes above
//! target_K. The extra samples of each kind are capped at `max_extra` x the model's total of
//! that kind and at `max_extra_samples` in all (per kind): while the boosts would cost more,
//! the target is raised by sqrt(2).
struct SamplingBoosts {
  std::vector<Node::SamplingBoost> boost;     //!< per node
  Eigen::VectorXd ir_standard_error_K;        //!< per node, estimated at the unboosted counts
  Eigen::VectorXd load_standard_error_K;      //!< per node, the same for the loads
  double target_K = 0.0;                      //!< the target actually used (>= the one asked)
  double extra_ir_rays = 0.0;                 //!< extra IR rays / the unboosted total
  double extra_load_samples = 0.0;            //!< extra sun + Earth samples / the unboosted total
  double ir_rays = 0.0;                       //!< the unboosted IR ray total
  double load_samples = 0.0;                  //!< the unboosted sun + Earth sample total (per side, not per step)
  SimulationResult unboosted;                 //!< the simulation the estimate comes from
  bool any() const;                           //!< some node boosted
  std::string summary(const std::vector<Node>& nodes) const;  //!< "dish IR x4 loads x2, ..."
  //! One line for progress output: the target, the extra samples and the summary.
  std::string describe(const std::vector<Node>& nodes) const;
};
//! With min_boost < 1 (reduce: 1/64), a kind of samples no node needs more of is *thinned*
//! when every node lies far under the target: all its nodes get the common multiplier
//! noise_targeted_thinning (a power of two in [min_boost, 1/4]); extra_* are then negative.
SamplingBoosts decide_sampling_boosts(const ThermalModel& model, const ModelSimulationSettings& settings,
                                      double target_K, double max_extra = 2.0,
                                      double max_extra_samples = std::numeric_limits<double>::infinity(),
                                      double min_boost = 1.0);

//! Whether any node of `model` already has a sampling boost (e.g. from its model file).
bool has_sampling_boosts(const ThermalModel& model);

//! Noise-targeted sampling as every front end's "simulate" applies it: the CLI's `simulate`
//! and `export`, the Python module, MeshLab and FreeCAD (reduce has its own target, a fraction
//! of its tolerance).
struct NoiseTargeting {
  //! Standard-error target per node [K]; 0 = off. The largest |dT| over every pair of 8 seeds,
  //! every node and every time step comes out at ~3-4x the per-node standard error
  //! (docs/thermal.md, "Noise-targeted sampling"), so 0.0025 K keeps the sample's
  //! seed-to-seed floor under 0.01 K.
  double target_K = 0.0025;
  //! At most this many extra IR rays, and extra sun/Earth samples, as a multiple of the
  //! model's totals (the target is raised until the boosts fit)...
  double budget = 32.0;
  //! ...and at most this many in all: the sample satellite needs 1.1e8 / 6.9e7 for its target
  //! (~10 s on 2 cores); a large CAD mesh, whose totals are many times the sample's, gets the
  //! multiple this leaves (its simulation stays within ~15 s of extra tracing instead of 32x
  //! its own run time).
  double max_samples = 2e8;
};

//! Decides the boosts (decide_sampling_boosts) and stores them in model.nodes[k].sampling_boost.
//! Nothing happens, and nothing is returned, when targeting is off (target_K <= 0) or the model
//! already has boosts (its file's are kept). Progress: the estimate and the decision.
std::optional<SamplingBoosts> apply_noise_targeting(ThermalModel& model, const ModelSimulationSettings& settings,
                                                    const NoiseTargeting& targeting = {});

//! One simulation as a front end runs it ("simulate this model"): apply_noise_targeting, then
//! simulate_model. The same model, settings and seed give bit-identical temperatures in every
//! front end. `model` receives the boosts decided.
struct FrontEndSimulation {
  SimulationResult result;
  NodeCouplings couplings;
  std::optional<SamplingBoosts> sampling;  //!< what noise targeting decided (none: off or kept)
};
FrontEndSimulation simulate_as_front_end(ThermalModel& model, const ModelSimulationSettings& settings = {},
                                         const NoiseTargeting& targeting = {});

//! Ray budgets for a bare mesh (a model loaded from a mesh file, ThermalModel::mesh_cleanup
//! set), sized by its face count F so that a simulation's cost stays bounded while the noise
//! floor stays well below the default 0.5 K tolerance (measured in docs/benchmarks.md,
//! "Reduction: NASA meshes"):
//!  - IR view factors: rays_per_face = clamp(kBareMeshIrRays / F, 1000, 4000) (a total of
//!    16 M rays: 4000 per face up to 4000 faces, fewer beyond);
//!  - sun shadows: sun_rays_per_face = clamp(kBareMeshSunRays / F, 256, 1024) and a per-node
//!    minimum of 400 000 samples: CAD panels are few, huge triangles whose partial shadows
//!    carry most of the load noise.
//! Model files keep their own settings (no-op when mesh_cleanup is unset).
void apply_bare_mesh_ray_budgets(ThermalModel& model, ModelSimulationSettings& settings);
constexpr double kBareMeshIrRays = 16e6;
constexpr double kBareMeshSunRays = 4e6;

//! Run-to-run Monte Carlo noise: the model simulated with `runs` seeds (seed, seed+1, ...),
//! every run compared with the first.
//! Seed-to-seed Monte Carlo noise: every pair of runs compared (not only each run against the
//! first, which would make the figure depend on how typical the first seed happens to be).
struct NoiseFloor {
  std::vector<std::uint64_t> seeds;
  std::vector<TemperatureDifference> differences;  //!< one per pair of runs, in `pairs` order
  std::vector<std::pair<int, int>> pairs;          //!< (i, j), i < j: indices into `seeds`
  TemperatureDifference worst;                     //!< the largest of them: the noise floor
  std::pair<int, int> worst_pair{0, 0};
  double median_abs_K = 0.0;                       //!< median over pairs of max |dT| [K]
  //! Per node (the first run's order): its worst pair, max over pairs and times of |dT| [K],
  //! with that pair and time: where the floor would be if only that node counted.
  struct NodeWorst {
    std::string node;
    double max_abs_K = 0.0;
    double time_s = 0.0;
    std::pair<int, int> pair{0, 0};  //!< indices into `seeds`
  };
  std::vector<NodeWorst> per_node;
  std::vector<double> run_time_s;                  //!< wall time of each run [s]
  SimulationResult first;                          //!< the first run's result
};

//! `first`, if given, is the first run's result (simulate_model(model, settings), e.g. a
//! reference already simulated): only runs 2..runs are simulated (and timed).
//! \throw InvalidInput if runs < 2.
NoiseFloor noise_floor(const ThermalModel& model, int runs = 3, const ModelSimulationSettings& settings = {},
                       const SimulationResult* first = nullptr);

//! The noise floor of runs already simulated: `results[k]` the model simulated with `seeds[k]`
//! (the same model and settings otherwise); every pair compared as noise_floor does (run_time_s
//! left empty). \throw InvalidInput if fewer than 2 runs or not one seed per run.
NoiseFloor noise_floor_of(std::vector<SimulationResult> results, std::vector<std::uint64_t> seeds);

}  // namespace thermodec
