#pragma once
// Private to core/src/environment: the state one external_loads() run shares between its
// passes (direct sun: direct_sun.h; Earth IR and albedo: earth_loads.h): the model's sides and
// time steps, the sample counts, the reference run being reused and the records being kept.
#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "change_reach.h"
#include "load_sides.h"
#include "occluders.h"
#include "ray_records.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/radiation/planar_strata.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::load_rays {

struct LoadRun {
  const ThermalModel& model;
  const RayScene& scene;
  const SurfaceSides& sides;
  const ExternalLoadSettings& settings;
  const std::function<void(const std::string&)>& progress;
  LoadSamples* samples;  // out, optional
  LoadReuse* reuse;      // optional
  const LoadSamples* ref;  // reuse->reference, or nullptr

  int num_nodes, ns;
  std::vector<Side> geo;
  Eigen::VectorXd alpha, eps;  // per side: absorptivity, emissivity

  bool orbit;
  int steps;      // positions + sunlit knots: the knots' states follow the positions'
  int positions;  // orbit positions k P / S (Loads::times_s)
  Eigen::VectorXd knot_times_s;   // Loads::knot_times_s: eclipse edges (sunlit side) and sun kinks
  std::vector<char> knot_is_edge;  // per knot: an eclipse edge (traced sunlit at the switch)
  Loads loads;  // the result being built
  double flux;  // solar flux [W/m^2]
  std::vector<OrbitState> states;  // per step

  // Sample counts per side (small nodes get more): a side whose count differs from its
  // reference twin's (its node gained or lost faces) draws other samples and is not reused.
  Eigen::VectorXi sun_rays, earth_rays;
  // Steady orbit with the sun moving in body axes (ExternalLoadSettings::steady_shadow_passes):
  // each shadow pass draws its own points, sun_rays_per_pass of them (sun_rays / division);
  // else division 1 and every pass draws sun_rays points.
  int shadow_division = 1;
  // Each shadow pass draws its own points (its own scramble seed): a steady orbit's passes
  // (division > 1) and a transient orbit's (ExternalLoadSettings::transient_shadow_passes,
  // division 1); else every pass traces the same points.
  bool own_shadow_points = false;
  Eigen::VectorXi sun_rays_per_pass;
  Eigen::MatrixXd sun_variance;  // #nodes x steps: variance [W^2] of the direct sun's shadow samples
  std::vector<int> ref_of;  // per side: its twin (same key) in the reference, -1 if none
  std::shared_ptr<const tracing::SobolTable> table;  // one Sobol table for every pass
  // Shadow control variates (ExternalLoadSettings::planar_shadow_controls, no reference): the
  // flat nodes' hulls and the concave caps' apertures (planar_node_hulls); empty = off.
  std::vector<NodeHull> shadow_hulls;
  Occluders occ;
  std::optional<ChangeReach> reach;  // with a reference: which sides the change can reach
  ChangeBox change_box;
  bool per_ray_reuse = false;
  std::vector<int> ref_side;  // per side: its twin's records, if it may read them, else -1
  std::atomic<long> reused_sun_rays{0}, traced_sun_rays{0}, reused_earth_rays{0}, traced_earth_rays{0};
  Recorder recorder;
  bool record = false;  // keeping per-ray records (reference runs only)
  std::vector<SideRays> recorded;

  // Solar-band incident power per side and step [W] (direct and albedo), absorbed shares.
  Eigen::MatrixXd incident_direct, incident_albedo;

  //! Validates the settings' environment, samples the time steps and maps the sides to the
  //! reference's. \throw InvalidInput as external_loads().
  LoadRun(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
          const ExternalLoadSettings& settings, const std::function<void(const std::string&)>& progress,
          LoadSamples* samples, LoadReuse* reuse);

  const tracing::SobolTable& sobol() const { return *table; }
  //! Side s has a reference twin with the same sample counts.
  bool same_counts(int s) const;
  //! The records of the pass that just ran, packed (pack_records); the per-side copies are
  //! freed at once (on large models they take several times the packed size).
  RayRecords take_records();
  //! The reuse and recording context of one ray pass reading `ref_records` (may be null).
  PassContext make_pass(const RayRecords* ref_records, std::atomic<long>* reused_rays, std::atomic<long>* traced_rays);
};

//! Direct sun with self-shadowing: fills run.incident_direct, run.loads.in_shadow and
//! run.sun_variance.
void direct_sun_loads(LoadRun& run);

//! Earth IR and albedo (orbit only): fills run.loads.earth_ir_W, run.incident_albedo and the
//! Earth rays' share of run.loads.sampling_standard_error_W (variances).
void earth_loads(LoadRun& run);

}  // namespace thermodec::load_rays
