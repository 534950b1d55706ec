#pragma once
//! Absorbed external loads of a model in its environment (fixed sun or circular orbit), per
//! thermal node and time step:
//!  - direct solar: S A max(0, n.s) x (fraction of the face's sample points that see the sun
//!    past the spacecraft itself), absorbed with the side's absorptivity; zero in eclipse;
//!  - albedo: each face side shoots cosine-weighted rays; those reaching the Earth sphere
//!    unblocked by the spacecraft carry a S max(0, n_earth(hit) . s) (a diffuse Lambertian
//!    Earth lit by the sun, so the terminator and the lit crescent seen from eclipse are
//!    resolved); absorbed with the absorptivity;
//!  - Earth IR: q_IR F_side->Earth (same rays), absorbed with the emissivity;
//!  - solar-band reflections: the unabsorbed part (1 - alpha) of direct + albedo power is
//!    reflected diffusely; solar Gebhart factors (radiation/gebhart_factors.h with the
//!    absorptivities) on the radiative engine's side-to-side view factors give the power each
//!    node finally absorbs. They depend on geometry only, so they are solved once per model.
//! Earth-IR reflections between faces are neglected (documented in docs/thermal.md).
//!
//! Sampling is stratified and jittered per side from a hash of the global seed and the side's
//! stable identity (SurfaceSides::key): unchanged faces keep their sample points and rays in a
//! modified model (correlated sampling), results are independent of thread count.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <functional>
#include <string>

#include "thermodec/environment/loads.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/ray_scene.h"
#include "thermodec/radiation/surface_sides.h"

namespace thermodec {

struct ExternalLoadSettings {
  int sun_rays_per_face = 256;    //!< shadow sample points per face side
  //! The first sun_pilot_rays points decide fully lit / fully shadowed sides; only the others
  //! trace all sun_rays_per_face (>= sun_rays_per_face disables the shortcut).
  int sun_pilot_rays = 64;
  //! Rays per face side towards the Earth for sides whose view of the Earth is partly blocked
  //! by the spacecraft (decided by the first earth_pilot_rays rays; unobstructed sides keep
  //! only those, the integrand being smooth there).
  int earth_rays_per_face = 4096;
  int earth_pilot_rays = 256;
  int steps_per_orbit = 0;        //!< orbit samples; 0 = model.analysis.steps_per_orbit
  std::uint64_t seed = 1;         //!< sampling seed (combined with each side's identity)
  bool solar_reflections = true;  //!< solar-band diffuse reflections between faces
};

//! Fraction of each side's hemisphere occupied by the Earth and not blocked by the spacecraft
//! (F_side->Earth) for an Earth centre at `earth_direction_body * distance_m` from the body
//! origin, estimated with `rays` cosine-weighted rays per side. Returns #sides.
Eigen::VectorXd earth_view_factors(const RayScene& scene, const SurfaceSides& sides,
                                   const Eigen::Vector3d& earth_direction_body, double distance_m,
                                   int rays, std::uint64_t seed);

//! Loads of `model` (whose mesh is scene.mesh() and whose sides are `sides`) in its
//! environment. `view_factors` (side-to-side, of the same sides) is needed for solar
//! reflections; pass nullptr to skip them. `progress` (optional) receives short messages.
//! \throw InvalidInput on bad settings (rays < 1, steps < 2 for an orbit) or environment.
Loads external_loads(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
                     const FaceViewFactors* view_factors, const ExternalLoadSettings& settings = {},
                     const std::function<void(const std::string&)>& progress = {});

}  // namespace thermodec
