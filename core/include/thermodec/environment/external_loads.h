#pragma once
//! Absorbed external loads of a model in its environment (fixed sun or circular orbit), per
//! thermal node and time step:
//!  - direct solar: S A max(0, n.s) x (fraction of the face's sample points that see the sun
//!    past the spacecraft itself), absorbed with the side's absorptivity; zero in eclipse;
//!  - albedo: each face side shoots rays into the cone the Earth subtends (uniform in solid
//!    angle, weight Omega_cap / (pi N) max(0, n.w)); those not blocked by the spacecraft carry
//!    a S max(0, n_earth(hit) . s) (a diffuse Lambertian Earth lit by the sun, so the
//!    terminator and the lit crescent seen from eclipse are resolved); absorbed with the
//!    absorptivity. When the Earth moves in body axes (sun / inertial attitudes) the rays are
//!    cosine-weighted over the hemisphere instead, traced once, and intersected with the
//!    Earth's cone at each step;
//!  - Earth IR: q_IR F_side->Earth (the sum of the same weights), absorbed with the emissivity;
//!  - solar-band reflections: the unabsorbed part (1 - alpha) of direct + albedo power is
//!    reflected diffusely; solar Gebhart factors (radiation/gebhart_factors.h with the
//!    absorptivities) on the radiative engine's side-to-side view factors give the power each
//!    node finally absorbs. They depend on geometry only, so they are solved once per model.
//! Earth-IR reflections between faces are neglected (documented in docs/thermal.md).
//!
//! Sampling: the ray stage's Owen-scrambled Sobol points (rays/sampling.h), scrambled per side from a
//! hash of the seed and the side's stable identity (SurfaceSides::key): unchanged faces keep
//! their sample points and rays in a modified model (correlated sampling), and results are
//! independent of thread count. Pilots (see the settings) spend the rays where a shadow or a
//! blocked Earth view makes the integrand discontinuous.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "thermodec/environment/loads.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec {

struct ExternalLoadSettings {
  int sun_rays_per_face = 256;    //!< shadow sample points per face side
  //! The first sun_pilot_rays points decide fully lit / fully shadowed sides; only the others
  //! trace all sun_rays_per_face (>= sun_rays_per_face disables the shortcut).
  int sun_pilot_rays = 256;
  //! Minimum shadow sample points for a node's partly shadowed sides: a node with n faces
  //! gives each such side max(sun_rays_per_face, ceil(sun_min_rays_per_node / n)); 0 = off.
  //! Every per-side count is rounded to a power of two (rays_per_side_of_node).
  int sun_min_rays_per_node = 50000;
  //! Rays per face side towards the Earth for sides whose view of the Earth may be blocked by
  //! the spacecraft; with the Earth fixed in body axes they set the rasterised view's origins
  //! (earth_view_by_rays). With rays, the first earth_pilot_rays decide which sides are partly
  //! blocked; unobstructed sides keep only those, the integrand being smooth there.
  int earth_rays_per_face = 1024;
  int earth_pilot_rays = 256;     //!< see earth_rays_per_face
  //! Minimum Earth rays for a node's partly blocked sides: a node with n faces gives each
  //! such side max(earth_rays_per_face, ceil(earth_min_rays_per_node / n)) (small nodes are
  //! otherwise the noisiest); 0 = earth_rays_per_face for all. Attitudes in which the Earth
  //! moves in body axes (sun, inertial) trace that many escaping hemisphere rays from every
  //! side (no pilot), with the same per-node minimum and noise-targeted boosts.
  int earth_min_rays_per_node = 200000;
  //! Earth fixed in body axes (nadir): the view of the Earth from a side that may be blocked
  //! is found by rasterising the faces that may block it over a fixed 64 x 64 grid of the
  //! Earth's cone, from one origin on the side per 64 of its Earth rays (at least 16): the
  //! seed then only moves the origins, and the blocked share seen from one origin is
  //! continuous in it (seed-to-seed variance / 8.5 against the cone rays on a partly blocked
  //! plate, docs/thermal.md). Sides whose blockers would cost more than their rays trace them.
  //! true: the cone rays for every side (a 4-D visibility indicator; reduction trials replay
  //! them from per-ray records).
  bool earth_view_by_rays = false;
  int steps_per_orbit = 0;        //!< orbit samples; 0 = model.analysis.steps_per_orbit
  //! Also trace the loads at every eclipse entry and exit, on the sunlit side (Loads::knot_*):
  //! two more sun passes per orbit.
  bool eclipse_edges = true;
  //! Also trace the loads where a face side turns edge-on to the sun between two positions, if
  //! a straight line over that kink could move some node by more than this [K] (see Loads::
  //! knot_*; 0 = off); at most max_kink_knots such instants (< 0: as many as positions).
  double kink_knot_threshold_K = 0.005;
  int max_kink_knots = -1;
  //! Steady analysis of an orbit whose sun moves in body axes: each shadow pass draws its own
  //! sample points, fewer of them (shadow_pass_division). false: every pass traces the same
  //! points, all of them.
  bool steady_shadow_passes = true;
  //! Transient analysis of an orbit whose sun moves in body axes: each shadow pass draws its own
  //! N sample points (its own scramble seed), all N of them, instead of the same N at every
  //! pass. The passes' shadow errors are then independent, and a node's temperature, which
  //! integrates its loads over its thermal time constant, averages them instead of following one
  //! error for the whole orbit (docs/thermal.md). The same rays either way. false: every pass
  //! traces the same points.
  bool transient_shadow_passes = true;
  //! Shadow control variates: the partly lit sides' sample points post-stratified by the
  //! flat nodes' hulls (and a concave cap's aperture for its own sides) that their sun rays
  //! cross, whose shares of the side are exact (docs/environment.md, "Shadow control
  //! variates"). `simulate` turns it on with the view factors' planar control variates
  //! (chain_load_settings); a reduction, whose trials re-trace single rays, leaves it off.
  bool planar_shadow_controls = false;
  std::uint64_t seed = 1;         //!< sampling seed (combined with each side's identity)
  bool solar_reflections = true;  //!< solar-band diffuse reflections between faces
  //! Memory cap [bytes] for the per-ray records of LoadSamples (what each sun and Earth ray
  //! met); beyond it none are kept and trials fall back to per-side reuse tests, which re-trace
  //! every ray of a side whose rays may meet the change. Juno's 17 k faces need 816 MB (402 M
  //! sun rays over 72 steps); at 512 MB its trials lost per-ray reuse.
  std::size_t ray_record_budget_bytes = std::size_t(2) << 30;
  //! Memory cap [bytes] for the Earth cone rays' origins and directions in those records (24
  //! bytes a ray; the sample's 2.2 M rays take 52 MB): a trial then tests the recorded rays of
  //! a side near the change as they are instead of generating them again. Beyond the cap none
  //! are kept and trials generate them (the same results, slower).
  std::size_t earth_ray_geometry_budget_bytes = std::size_t(512) << 20;
};

//! Shadow sample division of a steady orbit analysis with `shadow_passes` distinct sun
//! directions in body axes (sunlit positions): D = round(S^(2/3)), 1 for S <= 1.
//! A steady analysis uses the orbit mean of the loads only. When every pass draws its own
//! points (its own scramble) and N / D of them, the shadow errors of the passes are independent
//! and the orbit mean's error for a side lit in L of S passes is about sqrt(L) sigma(N / D) / S;
//! with one set of N points shared by every pass it is up to L sigma(N) / S (the passes' errors
//! then come from the same points). With Owen's sigma(N) ~ N^-3/4, D = S^(2/3) makes the two
//! equal for a side lit on every pass, at 1/D of the shadow rays. Seed-to-seed noise and
//! time, measured on CAD meshes: docs/benchmarks.md ("Thermal: shadow passes of a steady orbit").
int shadow_pass_division(int shadow_passes);

//! The division `model`'s loads use over its `shadow_passes` sunlit passes: shadow_pass_division
//! for a steady analysis of an orbit with settings.steady_shadow_passes, 1 otherwise. The one
//! place the loads (external_loads) and their cost estimate (thermal/simulation_cost.h) decide it.
int shadow_pass_division(const ThermalModel& model, const ExternalLoadSettings& settings, int shadow_passes);

//! Shadow sample points per side and pass: `rays` per side divided by `division`, rounded up,
//! and at least min(rays, 16) (a scrambled net's first strata).
Eigen::VectorXi shadow_rays_per_pass(const Eigen::VectorXi& rays, int division);

//! View factor from each side to the Earth, F_side->Earth = (1/pi) int cos(theta) V dw over
//! the Earth's cone, V = 0 where the spacecraft blocks the view, for an Earth centre at
//! `earth_direction_body * distance_m` [m] from the body origin; `rays` cone rays per side
//! (no pilot), or with `by_rays` false the rasterised view from raster_origins(rays) origins
//! (ExternalLoadSettings::earth_view_by_rays); `radius_m` is the central body's radius (the Earth's by default). Returns
//! #sides. \throw InvalidInput if rays < 1 or distance <= radius.
Eigen::VectorXd earth_view_factors(const RayScene& scene, const SurfaceSides& sides,
                                   const Eigen::Vector3d& earth_direction_body, double distance_m,
                                   int rays, std::uint64_t seed, double radius_m = 6371.0e3,
                                   bool by_rays = false);

//! View factor from a small plane element to the whole Earth seen unobstructed, for
//! cos_angle = cosine between the element's normal and the direction to the Earth's centre,
//! at `distance_m` [m] from the centre: cos/H^2 (H = distance / radius_m, the central body's
//! radius, the Earth's by default) while the body is all above the element's horizon, the
//! horizon-cut closed form in between, 0 below.
//! \throw InvalidInput if distance_m <= radius_m.
double unobstructed_earth_view_factor(double cos_angle, double distance_m, double radius_m = 6371.0e3);

//! What each traced ray of one ray family met, all sides concatenated in side order: side s
//! owns rays [ray_begin[s], ray_begin[s + 1]) (in the order the side generates them) and
//! blocker distances [hit_begin[s], hit_begin[s + 1]). One bit per ray (1 = blocked by the
//! spacecraft) and, per blocked ray in order, the distance [m] along its unit direction to its
//! closest blocker (NaN if unknown). Empty offsets = nothing recorded.
struct RayRecords {
  std::vector<std::uint64_t> blocked;
  std::vector<float> hit_m;
  std::vector<std::int64_t> ray_begin, hit_begin;  //!< #sides + 1 each
  //! Earth cone rays only (else empty), per ray: its sample index (the rays of a side facing
  //! away from the Earth's cone are skipped, so the k-th record is not always sample k) and its
  //! direction cell (16 x 16 equal-solid-angle cells of the cone), so that a trial can regenerate
  //! only the rays whose directions can reach the change.
  std::vector<std::uint32_t> sample_index;
  std::vector<std::uint8_t> cell;
  //! Earth cone rays only, per ray: cosine between the ray and the side's normal, so that a
  //! trial can rebuild a side's Earth hits after a few of its rays changed outcome without
  //! generating the others again.
  std::vector<float> cos_theta;
  //! Earth cone rays only, if they fit ExternalLoadSettings::earth_ray_geometry_budget_bytes
  //! (else empty), per ray: origin [m] and unit direction (body axes), 6 floats, exactly what
  //! the ray was traced with.
  std::vector<float> origin_direction;
  bool empty() const { return ray_begin.empty(); }
  std::size_t bytes() const {
    return blocked.size() * 8 + hit_m.size() * 4 + (ray_begin.size() + hit_begin.size()) * 8 +
           sample_index.size() * 4 + cell.size() + cos_theta.size() * 4 + origin_direction.size() * 4;
  }
};

//! What one external_loads run sampled per face side, the geometry-dependent part of the
//! loads: for a modified model (a trial of the reduction driver) the sides that did not
//! change and whose rays cannot reach the change reuse it instead of tracing again.
struct LoadSamples {
  std::vector<std::uint64_t> key;  //!< #sides identity (SurfaceSides::key)
  Eigen::MatrixXd sunlit;          //!< #sides x S lit fraction of the side's sun samples
  //! Per side: Earth rays kept, (weight, Earth normal at the hit) for an Earth fixed in body
  //! axes, else (1/N, escaping direction).
  std::vector<std::vector<std::pair<float, Eigen::Vector3f>>> earth;
  Eigen::VectorXd earth_view_factor;  //!< #sides F_side->Earth (Earth fixed in body axes)
  //! #sides relative binomial error of that view factor (0 for unobstructed sides), so that a
  //! side reused whole carries its sampling error into Loads::sampling_standard_error_W
  Eigen::VectorXd earth_relative_error;
  //! steps x #sides: sum over the side's Earth rays of w max(0, n_E . sun) (Earth fixed in
  //! body axes): a side reused whole reuses its albedo lighting at every step too.
  Eigen::MatrixXf earth_lit_per_step;
  //! #sides: could the spacecraft block the side's Earth view at all (conservative bounding-
  //! sphere test; it decides, with the pilot rays, how many rays the side traces)
  std::vector<char> earth_may_be_blocked;
  //! #sides x (#nodes + 2) solar-band Gebhart factors (reflections), the warm start of a
  //! trial's solve (empty if the run had no solar reflections)
  RowMatrixXd solar_gebhart;
  bool earth_fixed = true;
  Eigen::VectorXi sun_rays, earth_rays;  //!< #sides sample counts used (see the *_min_rays_per_node)
  //! Per-ray records (see RayRecords), kept when they fit settings.ray_record_budget_bytes:
  //! per step, the shadow rays traced at that step (empty where the step reused the previous
  //! sun direction or was in eclipse); the Earth cone rays (Earth fixed in body axes) or the
  //! hemisphere rays. A trial then re-traces only the rays whose path up to their reference
  //! blocker (or to infinity) enters the changed region.
  std::vector<RayRecords> sun_records;
  RayRecords earth_records;
  bool per_ray = false;  //!< the records are complete
  //! The run's sunlit knots (Loads::knot_times_s) and, per knot, whether it is an eclipse edge
  //! (traced sunlit at the switch): a trial traces the reference's knots, not its own, so that
  //! its steps match the reference's.
  Eigen::VectorXd knot_times_s;
  std::vector<char> knot_is_edge;
};

//! Reuse request: sides present in `reference` (same key) with the same sample counts whose
//! sun rays, Earth rays or hemisphere cannot reach `changed_region` (conservative bounding-
//! volume tests) take their samples from it whole; on the other such sides, with the
//! reference's per-ray records (LoadSamples::per_ray), each ray whose path up to its recorded
//! blocker (or to infinity) stays out of `changed_region` keeps its recorded result and only
//! the others are traced again. Either way the result equals a full run bit for bit.
//! `changed_region` [m, body axes] must bound the changed geometry before AND after the change
//! (what was removed can have shadowed others). Same environment and settings as the
//! reference run. A run given `reuse` records no per-ray records in its own `samples`.
//! `changed_faces` (optional): a scene of exactly the removed and the added triangles; a ray
//! that enters `changed_region` but meets none of them up to (just past) its recorded blocker,
//! or at all if it escaped, keeps its recorded result too (its blocker is unchanged, and no
//! new face lies on its way), instead of being traced again in the whole candidate.
struct LoadReuse {
  const LoadSamples* reference = nullptr;
  Eigen::AlignedBox3d changed_region;
  const RayScene* changed_faces = nullptr;
  // out: how much came from the reference: (side, sun direction) shadow evaluations and
  // sides' Earth rays reused whole / total; then, on the sides not reused whole, single rays
  // reused from the per-ray records / rays traced again.
  long reused_sun = 0, total_sun = 0;
  int reused_earth = 0, total_earth = 0;
  long reused_sun_rays = 0, traced_sun_rays = 0;
  long reused_earth_rays = 0, traced_earth_rays = 0;
  //! of the sides traced again, those replayed having generated only the rays whose direction
  //! cell can reach the change (the others kept their reference outcome unseen)
  int earth_sides_replayed_by_cells = 0;
};

//! Loads of `model` (whose mesh is scene.mesh() and whose sides are `sides`) in its
//! environment. `view_factors` (side-to-side, of the same sides) is needed for solar
//! reflections; pass nullptr to skip them. `progress` (optional) receives short messages.
//! `samples` (optional, out) records what was sampled for later reuse; `reuse` (optional)
//! takes unaffected sides from a reference run: the result is identical to a full run.
//! \throw InvalidInput on bad settings (rays < 1, steps < 2 for an orbit) or environment.
//! `solar_incident_W` (optional, out): #sides x steps solar-band power each side receives,
//! direct and albedo [W], what the reflections are computed from: with `view_factors` =
//! nullptr a caller can add them later (add_solar_reflections), e.g. once view factors
//! computed alongside are ready.
Loads external_loads(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
                     const FaceViewFactors* view_factors, const ExternalLoadSettings& settings = {},
                     const std::function<void(const std::string&)>& progress = {},
                     LoadSamples* samples = nullptr, LoadReuse* reuse = nullptr,
                     Eigen::MatrixXd* solar_incident_W = nullptr);

//! Adds the diffuse solar-band reflections between faces to `loads.reflected_solar_W`
//! (#nodes x steps [W]): a side receiving Q_s [W] (`solar_incident_W`, #sides x steps) absorbs
//! alpha_s Q_s itself (in solar_W / albedo_W already) and reflects (1 - alpha_s) Q_s, of which
//! node g finally absorbs the fraction B(s, g), the solar-band Gebhart factors over
//! `view_factors` (of the same sides). `warm` (optional): a reference run's samples, whose
//! Gebhart factors start the solve (sides matched by key); `samples` (optional, out) keeps
//! this run's factors for later runs.
//! \throw InvalidInput if the sizes disagree.
void add_solar_reflections(Loads& loads, const ThermalModel& model, const SurfaceSides& sides,
                           const FaceViewFactors& view_factors, const Eigen::MatrixXd& solar_incident_W,
                           const LoadSamples* warm = nullptr, LoadSamples* samples = nullptr);

}  // namespace thermodec
