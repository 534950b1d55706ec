#pragma once
//! A thermal model: the shared mesh plus nodes, materials, conductive links, environment,
//! analysis and radiation settings, as read from the JSON model file (docs/model-format.md).
//! All quantities SI: m, K, W, J/K, W/K, W/m^2.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "thermodec/mesh/bare_mesh_cleanup.h"
#include "thermodec/mesh/mesh.h"
#include "thermodec/nodes/central_body.h"
#include "thermodec/nodes/model_certificate.h"

namespace thermodec {

//! Diffuse grey thermo-optical properties of a coating.
struct Material {
  std::string name;
  double absorptivity = 0.5;  //!< solar absorptivity alpha in (0, 1]
  double emissivity = 0.5;    //!< IR hemispherical emissivity epsilon in (0, 1]
};

//! A heater switched by a thermostat on its own node's temperature (hysteresis band): on when
//! the node falls below on_K, off when it rises above off_K, unchanged in between
//! (thermal/transient.h: evaluated at the start of each solver step).
struct Thermostat {
  double on_K = 0.0;     //!< switch-on temperature [K], < off_K
  double off_K = 0.0;    //!< switch-off temperature [K]
  double power_W = 0.0;  //!< heater power while on [W], > 0
  bool operator==(const Thermostat& o) const { return on_K == o.on_K && off_K == o.off_K && power_W == o.power_W; }
};

//! A thermal node: an isothermal set of faces (same name as its mesh group).
struct Node {
  std::string name;
  int material = -1;                        //!< default material of its faces (index), -1 = model default
  double capacitance_J_per_K = 0.0;         //!< heat capacity C [J/K]; 0 = arithmetic (massless) node
  double power_W = 0.0;                     //!< internal dissipation Q [W]
  //! Time-varying internal dissipation over the orbit, piecewise constant: (t [s], Q [W]) pairs,
  //! t increasing from 0; Q applies from its t to the next pair's (the last's to the period P,
  //! then the schedule repeats every orbit). Every t must be < P. Empty = constant power_W;
  //! when set, it replaces power_W (which is then 0).
  std::vector<std::pair<double, double>> power_schedule_W;
  //! A thermostat heater on this node (transient orbit analyses only; a node with C > 0).
  std::optional<Thermostat> heater;
  std::optional<double> fixed_temperature_K;  //!< boundary node held at this temperature [K]
  //! Mixed into the sampling seeds of the node's faces (rays, sun and Earth samples); 0 in
  //! every normal run. Changing it redraws this node's samples only, with the same geometry:
  //! how the trial noise floor (reduction/reduction_reference.h) measures the Monte Carlo
  //! noise a reduction trial sees. Not stored in model files.
  std::uint64_t sampling_salt = 0;
  //! Multipliers (in [kMin, kMax]) of the Monte Carlo samples of the node's faces, per face and
  //! per node budgets alike: `ir` for the IR view-factor rays, `loads` for the sun points and
  //! Earth rays. Set by noise-targeted sampling (thermal/simulate_model.h,
  //! decide_sampling_boosts): > 1 for the nodes whose temperature the sampling noise moves most,
  //! < 1 on every node of a model `reduce` finds far oversampled; 1 otherwise. Stored in model
  //! files as "sampling_boost": {"ir": .., "loads": ..}.
  struct SamplingBoost {
    static constexpr double kMin = 1.0 / 64.0;
    static constexpr double kMax = 1e4;
    double ir = 1.0;
    double loads = 1.0;
    bool operator==(const SamplingBoost& o) const { return ir == o.ir && loads == o.loads; }
    bool operator!=(const SamplingBoost& o) const { return !(*this == o); }
  } sampling_boost;
};

//! Conductive link GL between two nodes [W/K].
struct Conductance {
  int from = -1;
  int to = -1;
  double conductance_W_per_K = 0.0;
};

enum class EnvironmentType { fixed_sun, orbit };
enum class Attitude { nadir, sun, inertial };

//! External heat sources. fixed_sun: deep space with a sun. orbit: circular orbit around a
//! central body (the Earth by default; nodes/central_body.h).
struct Environment {
  EnvironmentType type = EnvironmentType::orbit;
  Eigen::Vector3d sun_direction{1.0, 0.0, 0.0};  //!< fixed_sun: unit vector towards the sun, body axes
  double solar_flux_W_per_m2 = 1361.0;          //!< fixed_sun: flux; orbit: derived from the date
  double altitude_km = 500.0;
  double inclination_deg = 51.6;
  double raan_deg = 0.0;
  int day_of_year = 80;  //!< 1..366
  Attitude attitude = Attitude::nadir;
  //! orbit: the central body (set_central_body() fills these five from a CentralBody row).
  //! albedo and earth_ir_flux_W_per_m2 are the central body's Bond albedo and surface IR flux
  //! (the name is kept for the Earth, the default body).
  std::string central_body = "earth";
  double body_radius_m = 6371.0e3;                                 //!< R [m]
  double body_gravitational_parameter_m3_per_s2 = 3.986004418e14;  //!< GM [m^3/s^2]
  double sun_distance_au = 0.0;  //!< sets the solar flux; 0 = the Earth's on day_of_year
  double albedo = 0.30;
  double earth_ir_flux_W_per_m2 = 237.0;
};

//! Sets the environment's central body (name, radius, GM, sun distance, albedo, IR flux).
inline void set_central_body(Environment& env, const CentralBody& body) {
  env.central_body = body.name;
  env.body_radius_m = body.radius_m;
  env.body_gravitational_parameter_m3_per_s2 = body.gravitational_parameter_m3_per_s2;
  env.sun_distance_au = body.sun_distance_au;
  env.albedo = body.albedo;
  env.earth_ir_flux_W_per_m2 = body.ir_flux_W_per_m2;
}

//! The environment's central body as a CentralBody row.
inline CentralBody central_body_of(const Environment& env) {
  return CentralBody{env.central_body, env.body_radius_m, env.body_gravitational_parameter_m3_per_s2,
                     env.albedo, env.earth_ir_flux_W_per_m2, env.sun_distance_au};
}

enum class AnalysisType { steady, transient_orbit };

struct Analysis {
  AnalysisType type = AnalysisType::steady;
  int steps_per_orbit = 72;  //!< transient_orbit only: orbit positions where loads are ray traced
  int orbits = 3;            //!< transient_orbit: max orbits simulated to reach periodicity
  double time_tolerance_K = 0.01;  //!< transient_orbit: estimated time-discretization error target
};

//! Monte Carlo settings of the radiative engine.
struct RadiationSettings {
  //! Rays per face side (see min_rays_per_node; each side's count is rounded to a power of
  //! two, rays_per_side_of_node: 4000 gives 4096).
  int rays_per_face = 4000;
  std::uint64_t seed = 1;
  //! Minimum rays a node's faces emit in total (per side family: fronts, and backs if
  //! two-sided): a node with n faces gives each side max(rays_per_face,
  //! ceil(min_rays_per_node / n)) rays, so small nodes (a few faces) are estimated nearly as
  //! well as big ones. 0 = rays_per_face for every side. A side's count changes only when its
  //! own node's face count does (correlated sampling stays intact).
  int min_rays_per_node = 250000;
  //! Weigh each side's rays by control variates, the crossings of the flat nodes in front of
  //! it (radiation/planar_strata.h), whose unoccluded shares are known in closed form. Set by
  //! simulate_model (ModelSimulationSettings::planar_strata) and `viewfactors`, not stored in
  //! model files; a reduction's reference, whose rows are updated ray by ray, traces without it.
  bool planar_strata = false;
};

struct ThermalModel {
  //! Shared mesh. After loading, face_node indexes `nodes` and face_material indexes
  //! `materials` for every face (defaults resolved), and the name vectors of the mesh match.
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<Node> nodes;
  std::vector<Conductance> conductances;
  int default_material = 0;
  Environment environment;
  Analysis analysis;
  RadiationSettings radiation;
  double unit_scale = 1.0;             //!< mesh file units -> m (already applied to mesh.V)
  std::filesystem::path mesh_path;     //!< mesh file the model was read from
  //! Set when the model is a bare mesh cleaned on loading (nodes/load_model.h): what changed.
  std::optional<BareMeshCleanupReport> mesh_cleanup;
  //! Set on a reduced model (`reduce`): its verification against the original model.
  std::optional<ModelCertificate> certificate;
  //! Set on a model whose nodes were merged (`reduce --merge-nodes`, nodes/merge_nodes.h): per
  //! node of the original model, (its name, the name of the node it was merged into); empty
  //! otherwise. Stored in model files as "node_map": {"original": "merged", ...}.
  std::vector<std::pair<std::string, std::string>> node_map;
};

}  // namespace thermodec
