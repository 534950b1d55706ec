// pybind11 module `thermodec`: the core's plain data (Mesh, ThermalModel and its parts) and
// its free functions, for the FreeCAD workbench and scripts. It only binds: every algorithm
// and every check lives in the core, so Python sees the same errors as the CLI.
//
// Eigen matrices cross as numpy arrays (copies; numpy is row-major, Eigen column-major).
// The model's node/material/conductance lists are opaque vectors so that
// `model.nodes.append(n)` and `model.nodes[0].power_W = 5` change the model in place.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <optional>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <pybind11/stl_bind.h>

#include "thermodec/exchange/export_model.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/mesh/io.h"
#include "thermodec/mesh/mesh.h"
#include "thermodec/mesh/mesh_stats.h"
#include "thermodec/mesh/weld.h"
#include "thermodec/nodes/automatic_nodes.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/reduction/merge_reduction.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/report/reduction_report.h"
#include "thermodec/thermal/result_json.h"
#include "thermodec/thermal/simulate_model.h"
#include "thermodec/thermal/simulation_cost.h"

namespace py = pybind11;
using namespace thermodec;

PYBIND11_MAKE_OPAQUE(std::vector<thermodec::Material>)
PYBIND11_MAKE_OPAQUE(std::vector<thermodec::Node>)
PYBIND11_MAKE_OPAQUE(std::vector<thermodec::Conductance>)

namespace {

// How a Python caller overrides the core's cost refusal (thermal/simulation_cost.h).
constexpr const char* kForceHint = "pass force=True to run anyway";

void bind_errors(py::module_& m) {
  // Translators run newest first, so the base goes first and each subclass is caught as itself.
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<InvalidInput> invalid_input(m, "InvalidInput", error.ptr());
  static py::exception<IOError> io_error(m, "IOError", error.ptr());
  static py::exception<SolverError> solver_error(m, "SolverError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidInput& e) {
      invalid_input(e.what());
    } catch (const IOError& e) {
      io_error(e.what());
    } catch (const SolverError& e) {
      solver_error(e.what());
    } catch (const Error& e) {
      error(e.what());
    }
  });
}

void bind_mesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", "Indexed triangle mesh with per-face node, material and sidedness (SI: m).")
      .def(py::init<>())
      .def(py::init([](const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
             Mesh mesh;
             mesh.V = V;
             mesh.F = F;
             const Eigen::Index n = F.rows();
             mesh.face_node = Eigen::VectorXi::Constant(n, -1);
             mesh.face_material = Eigen::VectorXi::Constant(n, -1);
             mesh.face_back_material = Eigen::VectorXi::Constant(n, -1);
             return mesh;
           }),
           py::arg("V"), py::arg("F"),
           "Mesh from #Vx3 positions [m] and #Fx3 vertex indices; every face unassigned (-1).")
      .def_readwrite("V", &Mesh::V, "#V x 3 vertex positions [m]")
      .def_readwrite("F", &Mesh::F, "#F x 3 vertex indices, counter-clockwise seen from the front")
      .def_readwrite("face_node", &Mesh::face_node, "#F node index per face, -1 = unassigned")
      .def_readwrite("face_material", &Mesh::face_material, "#F front material index, -1 = the node's")
      .def_readwrite("face_back_material", &Mesh::face_back_material,
                     "#F back material index, -1 = one-sided")
      .def_readwrite("node_names", &Mesh::node_names)
      .def_readwrite("material_names", &Mesh::material_names)
      .def_property_readonly("num_vertices", &Mesh::num_vertices)
      .def_property_readonly("num_faces", &Mesh::num_faces)
      .def("__repr__", [](const Mesh& mesh) {
        return "<thermodec.Mesh " + std::to_string(mesh.num_vertices()) + " vertices, " +
               std::to_string(mesh.num_faces()) + " faces, " + std::to_string(mesh.node_names.size()) +
               " nodes>";
      });

  py::class_<MeshReadOptions>(m, "MeshReadOptions")
      .def(py::init<>())
      .def_readwrite("weld_tolerance", &MeshReadOptions::weld_tolerance)
      .def_readwrite("drop_degenerate_faces", &MeshReadOptions::drop_degenerate_faces);
  py::class_<MeshReadReport>(m, "MeshReadReport")
      .def(py::init<>())
      .def_readwrite("welded_vertices", &MeshReadReport::welded_vertices)
      .def_readwrite("degenerate_faces", &MeshReadReport::degenerate_faces)
      .def_readwrite("degenerate_faces_dropped", &MeshReadReport::degenerate_faces_dropped);
  py::class_<MeshWriteOptions>(m, "MeshWriteOptions")
      .def(py::init<>())
      .def_readwrite("binary", &MeshWriteOptions::binary)
      .def_readwrite("protected_inputs", &MeshWriteOptions::protected_inputs);
  py::class_<MeshStats>(m, "MeshStats")
      .def(py::init<>())
      .def_readwrite("faces", &MeshStats::faces)
      .def_readwrite("vertices", &MeshStats::vertices)
      .def_readwrite("unreferenced_vertices", &MeshStats::unreferenced_vertices)
      .def_readwrite("edges", &MeshStats::edges)
      .def_readwrite("components", &MeshStats::components)
      .def_readwrite("boundary_edges", &MeshStats::boundary_edges)
      .def_readwrite("non_manifold_edges", &MeshStats::non_manifold_edges)
      .def_readwrite("degenerate_faces", &MeshStats::degenerate_faces)
      .def_readwrite("area_m2", &MeshStats::area_m2);
  py::class_<WeldResult>(m, "WeldResult")
      .def_readonly("V", &WeldResult::V)
      .def_readonly("new_index", &WeldResult::new_index);
  py::class_<AutomaticNodeOptions>(m, "AutomaticNodeOptions")
      .def(py::init<>())
      .def_readwrite("max_normal_deviation_deg", &AutomaticNodeOptions::max_normal_deviation_deg)
      .def_readwrite("min_node_area_fraction", &AutomaticNodeOptions::min_node_area_fraction)
      .def_readwrite("max_nodes", &AutomaticNodeOptions::max_nodes);
}

void bind_model(py::module_& m) {
  py::class_<Material>(m, "Material", "Diffuse grey coating: solar absorptivity, IR emissivity.")
      .def(py::init([](std::string name, double absorptivity, double emissivity) {
             return Material{std::move(name), absorptivity, emissivity};
           }),
           py::arg("name") = "", py::arg("absorptivity") = 0.5, py::arg("emissivity") = 0.5)
      .def_readwrite("name", &Material::name)
      .def_readwrite("absorptivity", &Material::absorptivity)
      .def_readwrite("emissivity", &Material::emissivity)
      .def("__repr__", [](const Material& mat) {
        return "<thermodec.Material " + mat.name + " a=" + std::to_string(mat.absorptivity) +
               " e=" + std::to_string(mat.emissivity) + ">";
      });

  py::class_<Thermostat>(m, "Thermostat", "Thermostat heater: on below on_K, off above off_K, power_W while on.")
      .def(py::init([](double on_K, double off_K, double power_W) { return Thermostat{on_K, off_K, power_W}; }),
           py::arg("on_K") = 0.0, py::arg("off_K") = 0.0, py::arg("power_W") = 0.0)
      .def_readwrite("on_K", &Thermostat::on_K)
      .def_readwrite("off_K", &Thermostat::off_K)
      .def_readwrite("power_W", &Thermostat::power_W);

  py::class_<Node>(m, "Node", "Isothermal node (SI: J/K, W, K).")
      .def(py::init([](std::string name, int material, double capacitance_J_per_K, double power_W,
                       std::optional<double> fixed_temperature_K) {
             Node n;
             n.name = std::move(name);
             n.material = material;
             n.capacitance_J_per_K = capacitance_J_per_K;
             n.power_W = power_W;
             n.fixed_temperature_K = fixed_temperature_K;
             return n;
           }),
           py::arg("name") = "", py::arg("material") = -1, py::arg("capacitance_J_per_K") = 0.0,
           py::arg("power_W") = 0.0, py::arg("fixed_temperature_K") = py::none())
      .def_readwrite("name", &Node::name)
      .def_readwrite("material", &Node::material)
      .def_readwrite("capacitance_J_per_K", &Node::capacitance_J_per_K)
      .def_readwrite("power_W", &Node::power_W)
      .def_readwrite("power_schedule_W", &Node::power_schedule_W, "[(t_s, W), ...] over the orbit (replaces power_W)")
      .def_readwrite("heater", &Node::heater, "Thermostat or None")
      .def_readwrite("fixed_temperature_K", &Node::fixed_temperature_K);

  py::class_<Conductance>(m, "Conductance", "Conductive link between two node indices [W/K].")
      .def(py::init([](int from, int to, double conductance_W_per_K) {
             return Conductance{from, to, conductance_W_per_K};
           }),
           py::arg("from_node") = -1, py::arg("to_node") = -1, py::arg("conductance_W_per_K") = 0.0)
      .def_readwrite("from_node", &Conductance::from)
      .def_readwrite("to_node", &Conductance::to)
      .def_readwrite("conductance_W_per_K", &Conductance::conductance_W_per_K);

  py::bind_vector<std::vector<Material>>(m, "MaterialList");
  py::bind_vector<std::vector<Node>>(m, "NodeList");
  py::bind_vector<std::vector<Conductance>>(m, "ConductanceList");

  py::enum_<EnvironmentType>(m, "EnvironmentType")
      .value("fixed_sun", EnvironmentType::fixed_sun)
      .value("orbit", EnvironmentType::orbit);
  py::enum_<Attitude>(m, "Attitude")
      .value("nadir", Attitude::nadir)
      .value("sun", Attitude::sun)
      .value("inertial", Attitude::inertial);
  py::class_<Environment>(m, "Environment")
      .def(py::init<>())
      .def_readwrite("type", &Environment::type)
      .def_readwrite("sun_direction", &Environment::sun_direction)
      .def_readwrite("solar_flux_W_per_m2", &Environment::solar_flux_W_per_m2)
      .def_readwrite("altitude_km", &Environment::altitude_km)
      .def_readwrite("inclination_deg", &Environment::inclination_deg)
      .def_readwrite("raan_deg", &Environment::raan_deg)
      .def_readwrite("day_of_year", &Environment::day_of_year)
      .def_readwrite("attitude", &Environment::attitude)
      .def_readwrite("albedo", &Environment::albedo)
      .def_readwrite("earth_ir_flux_W_per_m2", &Environment::earth_ir_flux_W_per_m2)
      .def_readonly("central_body", &Environment::central_body)
      .def_readwrite("body_radius_m", &Environment::body_radius_m)
      .def_readwrite("body_gravitational_parameter_m3_per_s2", &Environment::body_gravitational_parameter_m3_per_s2)
      .def_readwrite("sun_distance_au", &Environment::sun_distance_au)
      .def(
          "set_central_body",
          [](Environment& e, const std::string& name) {
            const CentralBody* b = find_central_body(name);
            if (!b) throw InvalidInput("unknown central body '" + name + "'");
            set_central_body(e, *b);
          },
          py::arg("name"), "earth, moon or mars: radius, GM, albedo, IR flux and sun distance of that body");

  py::enum_<AnalysisType>(m, "AnalysisType")
      .value("steady", AnalysisType::steady)
      .value("transient_orbit", AnalysisType::transient_orbit);
  py::class_<Analysis>(m, "Analysis")
      .def(py::init<>())
      .def_readwrite("type", &Analysis::type)
      .def_readwrite("steps_per_orbit", &Analysis::steps_per_orbit)
      .def_readwrite("time_tolerance_K", &Analysis::time_tolerance_K)
      .def_readwrite("orbits", &Analysis::orbits);
  py::class_<LoadCase>(m, "LoadCase", "Another environment + analysis for the same model (nodes/load_case.h).")
      .def(py::init<>())
      .def_readwrite("name", &LoadCase::name)
      .def_readwrite("environment", &LoadCase::environment)
      .def_readwrite("analysis", &LoadCase::analysis);

  py::class_<RadiationSettings>(m, "RadiationSettings")
      .def(py::init<>())
      .def_readwrite("rays_per_face", &RadiationSettings::rays_per_face, "rays per face side (at least)")
      .def_readwrite("seed", &RadiationSettings::seed)
      .def_readwrite("min_rays_per_node", &RadiationSettings::min_rays_per_node,
                     "minimum rays a node's faces emit in total (small nodes get more per face); 0 = off");

  py::class_<ThermalModel>(m, "ThermalModel", "Shared mesh + nodes, materials, links, environment (SI).")
      .def(py::init<>())
      .def_readwrite("mesh", &ThermalModel::mesh)
      .def_readwrite("materials", &ThermalModel::materials)
      .def_readwrite("nodes", &ThermalModel::nodes)
      .def_readwrite("conductances", &ThermalModel::conductances)
      .def_readwrite("default_material", &ThermalModel::default_material)
      .def_readwrite("environment", &ThermalModel::environment)
      .def_readwrite("analysis", &ThermalModel::analysis)
      .def_readwrite("radiation", &ThermalModel::radiation)
      .def_readwrite("unit_scale", &ThermalModel::unit_scale)
      .def_readwrite("mesh_path", &ThermalModel::mesh_path)
      .def_readwrite("node_map", &ThermalModel::node_map,
                     "[(original, merged)] of a model whose nodes were merged; empty otherwise");
}

void bind_results(py::module_& m) {
  py::class_<Loads>(m, "Loads", "Absorbed external loads, N nodes x S times [W].")
      .def_readonly("times_s", &Loads::times_s)
      .def_readonly("period_s", &Loads::period_s)
      .def_readonly("solar_W", &Loads::solar_W)
      .def_readonly("albedo_W", &Loads::albedo_W)
      .def_readonly("earth_ir_W", &Loads::earth_ir_W)
      .def_readonly("reflected_solar_W", &Loads::reflected_solar_W)
      .def_readonly("in_shadow", &Loads::in_shadow)
      .def("total_W", &Loads::total_W);
  py::class_<OrbitEnergy>(m, "OrbitEnergy")
      .def_readonly("absorbed_J", &OrbitEnergy::absorbed_J)
      .def_readonly("emitted_J", &OrbitEnergy::emitted_J)
      .def_readonly("to_boundary_J", &OrbitEnergy::to_boundary_J)
      .def_readonly("stored_J", &OrbitEnergy::stored_J)
      .def("relative_imbalance", &OrbitEnergy::relative_imbalance);
  py::class_<SimulationResult>(m, "SimulationResult", "Temperatures of N nodes (model order) at S times.")
      .def_readonly("nodes", &SimulationResult::nodes)
      .def_readonly("times_s", &SimulationResult::times_s)
      .def_readonly("temperature_K", &SimulationResult::temperature_K, "N x S [K]")
      .def_readonly("loads", &SimulationResult::loads)
      .def_readonly("internal_power_W", &SimulationResult::internal_power_W)
      .def_readonly("transient", &SimulationResult::transient)
      .def_readonly("orbits", &SimulationResult::orbits)
      .def_readonly("periodicity_residual_K", &SimulationResult::periodicity_residual_K)
      .def_readonly("time_error_K", &SimulationResult::time_error_K)
      .def_readonly("energy", &SimulationResult::energy)
      .def("to_json", [](const SimulationResult& r) {
        // The result file's own format (thermal/result_json.h), as Python objects.
        return py::module_::import("json").attr("loads")(result_to_json(r).dump());
      });
  py::class_<TemperatureDifference>(m, "TemperatureDifference")
      .def_readonly("max_abs_K", &TemperatureDifference::max_abs_K)
      .def_readonly("node", &TemperatureDifference::node)
      .def_readonly("time_s", &TemperatureDifference::time_s)
      .def_readonly("time_index", &TemperatureDifference::time_index);

  py::class_<DecimationOptions>(m, "DecimationOptions")
      .def(py::init<>())
      .def_readwrite("max_relative_area_change", &DecimationOptions::max_relative_area_change)
      .def_readwrite("max_relative_volume_change", &DecimationOptions::max_relative_volume_change)
      .def_readwrite("max_contour_deviation", &DecimationOptions::max_contour_deviation)
      .def_readwrite("max_normal_deviation_deg", &DecimationOptions::max_normal_deviation_deg)
      .def_readwrite("shape_weight", &DecimationOptions::shape_weight)
      .def_readwrite("unassigned_ratio", &DecimationOptions::unassigned_ratio)
      .def_readwrite("min_faces_per_node", &DecimationOptions::min_faces_per_node)
      .def_readwrite("area_neutral_placement", &DecimationOptions::area_neutral_placement);
  py::class_<NodeDecimationStats>(m, "NodeDecimationStats")
      .def_readonly("faces_before", &NodeDecimationStats::faces_before)
      .def_readonly("faces_after", &NodeDecimationStats::faces_after)
      .def_readonly("target_faces", &NodeDecimationStats::target_faces)
      .def_readonly("area_before_m2", &NodeDecimationStats::area_before_m2)
      .def_readonly("area_after_m2", &NodeDecimationStats::area_after_m2)
      .def_readonly("reached", &NodeDecimationStats::reached)
      .def("relative_area_change", &NodeDecimationStats::relative_area_change);
  py::class_<DecimationResult>(m, "DecimationResult")
      .def_readonly("mesh", &DecimationResult::mesh)
      .def_readonly("fine_face_of_coarse", &DecimationResult::fine_face_of_coarse)
      .def_readonly("coarse_face_of_fine", &DecimationResult::coarse_face_of_fine)
      .def_readonly("fine_vertex_of_coarse", &DecimationResult::fine_vertex_of_coarse)
      .def_readonly("nodes", &DecimationResult::nodes)
      .def_readonly("closed_volume_before_m3", &DecimationResult::closed_volume_before_m3)
      .def_readonly("closed_volume_after_m3", &DecimationResult::closed_volume_after_m3)
      .def_readonly("collapses", &DecimationResult::collapses);
}

void bind_reduction(py::module_& m) {
  py::enum_<ReductionStrategy>(m, "ReductionStrategy")
      .value("informed", ReductionStrategy::informed)
      .value("uniform", ReductionStrategy::uniform);
  py::class_<ReduceSettings>(m, "ReduceSettings",
                             "Main settings of reduce_model; the nested ones keep their defaults.")
      .def(py::init<>())
      .def_readwrite("tolerance_K", &ReduceSettings::tolerance_K)
      .def_readwrite("strategy", &ReduceSettings::strategy)
      .def_readwrite("noise_runs", &ReduceSettings::noise_runs)
      .def_readwrite("sensitivity_cap_factor", &ReduceSettings::sensitivity_cap_factor)
      .def_readwrite("noise_target_fraction", &ReduceSettings::noise_target_fraction)
      .def_readwrite("thin_oversampling", &ReduceSettings::thin_oversampling,
                     "a model far under the noise target traces fewer samples (one common factor, 1/4 to 1/64)")
      .def_readwrite("area_error_fraction", &ReduceSettings::area_error_fraction,
                     "area drift may cost at most this fraction of the tolerance (sets the decimator's area bound)")
      .def_readwrite("prediction_targets", &ReduceSettings::prediction_targets)
      .def_readwrite("extra_cases", &ReduceSettings::extra_cases,
                     "further load cases (LoadCase) the reduced model must also meet; trials take the worst")
      .def_readwrite("progress", &ReduceSettings::progress,
                     "progress(line): may be called from worker threads");
  py::class_<NodeReduction>(m, "NodeReduction")
      .def_readonly("name", &NodeReduction::name)
      .def_readonly("faces_before", &NodeReduction::faces_before)
      .def_readonly("faces_after", &NodeReduction::faces_after)
      .def_readonly("requested_ratio", &NodeReduction::requested_ratio)
      .def_readonly("ratio", &NodeReduction::ratio)
      .def_readonly("predicted_ratio", &NodeReduction::predicted_ratio)
      .def_readonly("max_abs_dT_K", &NodeReduction::max_abs_dT_K)
      .def_readonly("area_before_m2", &NodeReduction::area_before_m2)
      .def_readonly("area_after_m2", &NodeReduction::area_after_m2);
  py::class_<CaseResult>(m, "CaseResult", "The verified reduced model in one load case.")
      .def_readonly("name", &CaseResult::name)
      .def_readonly("noise_floor_K", &CaseResult::noise_floor_K)
      .def_readonly("max_temperature_difference_K", &CaseResult::max_temperature_difference_K)
      .def_readonly("max_difference_node", &CaseResult::max_difference_node)
      .def_readonly("max_difference_time_s", &CaseResult::max_difference_time_s);
  py::class_<ReductionRun>(m, "ReductionRun", "Outcome of reduce_model (verified by a full recompute).")
      .def_readonly("strategy", &ReductionRun::strategy)
      .def_readonly("tolerance_K", &ReductionRun::tolerance_K)
      .def_readonly("noise_floor_K", &ReductionRun::noise_floor_K)
      .def_readonly("max_relative_area_change", &ReductionRun::max_relative_area_change)
      .def_readonly("faces_before", &ReductionRun::faces_before)
      .def_readonly("faces_after", &ReductionRun::faces_after)
      .def_readonly("max_temperature_difference_K", &ReductionRun::max_temperature_difference_K)
      .def_readonly("max_difference_node", &ReductionRun::max_difference_node)
      .def_readonly("max_difference_case", &ReductionRun::max_difference_case)
      .def_readonly("max_difference_time_s", &ReductionRun::max_difference_time_s)
      .def_readonly("nodes", &ReductionRun::nodes)
      .def_readonly("cases", &ReductionRun::cases, "the model's own case first, then extra_cases")
      .def_readonly("trials", &ReductionRun::trials)
      .def_readonly("seconds_total", &ReductionRun::seconds_total)
      .def_property_readonly("reduced_model", [](const ReductionRun& r) { return r.reduced.model; })
      .def_property_readonly("reduced_result", [](const ReductionRun& r) { return r.reduced.result; })
      .def_readonly("reference", &ReductionRun::reference)
      .def_property_readonly("node_map", [](const ReductionRun& r) { return r.reduced.model.node_map; },
                             "[(original, merged)] when nodes were merged (reduce_with_node_merging); else empty");
  py::class_<NodeMergeSettings>(m, "NodeMergeSettings", "Node merging of reduce_with_node_merging (--merge-nodes).")
      .def(py::init<>())
      .def_readwrite("keep", &NodeMergeSettings::keep, "node name patterns never merged (--keep-node)")
      .def_readwrite("tolerance_share", &NodeMergeSettings::tolerance_share,
                     "share of the tolerance the merges may spend (--merge-share)")
      .def_readwrite("signed_budgets", &NodeMergeSettings::signed_budgets,
                     "budgets charged by the sign of each merge's difference (--merge-signed-budgets)")
      .def_readwrite("small_node_share", &NodeMergeSettings::small_node_share,
                     "share of the tolerance small nodes may take from the merges (--merge-small-share; off at <= tolerance_share)")
      .def_readwrite("strongest_exchanges", &NodeMergeSettings::strongest_exchanges)
      .def_readwrite("confirm_by_tracing", &NodeMergeSettings::confirm_by_tracing);
}

void bind_functions(py::module_& m) {
  using release = py::call_guard<py::gil_scoped_release>;

  // mesh/io.h
  m.def("read_mesh", py::overload_cast<const std::filesystem::path&, const MeshReadOptions&>(&read_mesh),
        py::arg("path"), py::arg("options") = MeshReadOptions{}, release{},
        "Reads an OBJ/PLY/STL mesh (groups -> nodes, usemtl -> materials). Raises IOError, InvalidInput.");
  m.def("read_mesh_with_report",
        [](const std::filesystem::path& path, const MeshReadOptions& options) {
          MeshReadReport report;
          Mesh mesh = read_mesh(path, options, report);
          return py::make_tuple(std::move(mesh), std::move(report));
        },
        py::arg("path"), py::arg("options") = MeshReadOptions{},
        "(Mesh, MeshReadReport): read_mesh that reports welding and dropped faces instead of logging.");
  m.def("write_mesh", &write_mesh, py::arg("path"), py::arg("mesh"),
        py::arg("options") = MeshWriteOptions{}, release{},
        "Writes a mesh atomically; format from the extension (.obj .ply .stl).");

  // mesh/weld.h, mesh/face_geometry.h, mesh/mesh_stats.h
  m.def("weld_vertices", &weld_vertices, py::arg("V"), py::arg("tolerance"),
        "Merges vertices closer than tolerance (units of V) into the first of them; WeldResult.");
  m.def("face_areas", &face_areas, py::arg("V"), py::arg("F"), "#F face areas [m^2 if V in m]");
  m.def("face_normals", &face_normals, py::arg("V"), py::arg("F"), "#F x 3 unit normals");
  m.def("degenerate_faces", &degenerate_faces, py::arg("V"), py::arg("F"));
  m.def("face_components", &face_components, py::arg("F"), "#F edge-connected component id per face");
  m.def("mesh_stats", &mesh_stats, py::arg("mesh"));
  m.def("node_face_counts", &node_face_counts, py::arg("mesh"));
  m.def("node_areas_m2", &node_areas_m2, py::arg("mesh"));
  m.def("node_materials", &node_materials, py::arg("mesh"));

  // nodes/load_model.h
  m.def("load_model", py::overload_cast<const std::filesystem::path&>(&load_model), py::arg("path"),
        release{}, "Reads a model.json (or a bare mesh) into a ThermalModel. Raises InvalidInput naming the key.");
  m.def("load_model", py::overload_cast<const std::filesystem::path&, const MeshReadOptions&>(&load_model),
        py::arg("path"), py::arg("mesh_options"), release{});
  m.def("load_case", &load_case, py::arg("path"), py::arg("base"), release{},
        "Reads a load case file over base's environment and analysis. Raises InvalidInput naming the key.");
  m.def("own_case", &own_case, py::arg("model"), py::arg("name") = "model");
  m.def("with_case", &with_case, py::arg("model"), py::arg("case"), "the model in that case's environment");
  m.def("save_model", &save_model, py::arg("model"), py::arg("json_path"), py::arg("mesh_path"), release{},
        "Writes the model JSON and its mesh atomically.");

  // thermal/simulate_model.h, thermal/result_json.h
  m.def("simulate_model",
        [](ThermalModel model, std::function<void(const std::string&)> progress, std::optional<std::uint64_t> seed,
           double noise_target_K, bool force) {
          ModelSimulationSettings settings;
          if (progress) {
            settings.progress = [progress](const std::string& message) {
              py::gil_scoped_acquire gil;
              progress(message);
            };
          }
          if (seed) model.radiation.seed = *seed;
          NoiseTargeting noise;
          noise.target_K = noise_target_K;
          refuse_costly_run(check_front_end_simulation_cost(model, settings, noise), force, kForceHint);
          py::gil_scoped_release unlocked;
          return simulate_as_front_end(model, settings, noise).result;
        },
        py::arg("model"), py::arg("progress") = nullptr, py::arg("seed") = py::none(),
        py::arg("noise_target_K") = NoiseTargeting{}.target_K, py::arg("force") = false,
        "The simulation `thermodec simulate` runs (thermal/simulate_model.h, simulate_as_front_end): "
        "noise-targeted sampling (noise_target_K [K], 0 = off; boosts already in the model are kept), "
        "then couplings, external loads, solve; bit-identical to the CLI's for the same model and seed "
        "(seed: None = the model's radiation.seed). progress(message) is called with stage names. "
        "A run the core estimates over its cost limits is refused before any work unless force=True "
        "(as the CLI's --force). Raises InvalidInput, SolverError.");
  // exchange/export_model.h
  m.def("export_model",
        [](const ThermalModel& model, const std::string& format, const std::filesystem::path& out, const std::string& stem,
           std::function<void(const std::string&)> progress, bool force) {
          ExportSettings settings;
          settings.title = model.mesh_path.string();
          settings.protected_inputs = {model.mesh_path};
          if (progress) {
            settings.simulation.progress = [progress](const std::string& message) {
              py::gil_scoped_acquire gil;
              progress(message);
            };
          }
          // An unknown name is refused before any work, and so is a costly simulation.
          if (export_format(format).needs_simulation)
            refuse_costly_run(check_front_end_simulation_cost(model, settings.simulation, settings.noise), force,
                              kForceHint);
          py::gil_scoped_release unlocked;
          return export_model(model, format, out, stem, settings);
        },
        py::arg("model"), py::arg("format"), py::arg("out"), py::arg("stem") = "model", py::arg("progress") = nullptr,
        py::arg("force") = false,
        "`thermodec export`: format = a name of export_formats() (out = a file, a folder or a prefix as its "
        "'output' says); returns the files written (docs/exchange.md); force as for simulate_model. "
        "Raises InvalidInput, SolverError.");
  // exchange/export_formats.h
  m.def(
      "export_formats",
      [] {
        py::list rows;
        for (const ExportFormat& f : export_formats()) {
          py::dict row;
          row["name"] = f.name;
          row["title"] = f.title;
          row["extensions"] = f.extensions;
          row["only_these_extensions"] = f.only_these_extensions;
          row["output"] = f.output == ExportOutput::file ? "file" : f.output == ExportOutput::folder ? "folder" : "prefix";
          row["needs_simulation"] = f.needs_simulation;
          row["help"] = f.help;
          rows.append(row);
        }
        return rows;
      },
      "The export formats, in menu order, as the CLI's `export --format` offers them: dicts with name, title, "
      "extensions (the first the default), only_these_extensions, output ('file', 'folder' or 'prefix'), "
      "needs_simulation and help (exchange/export_formats.h).");
  m.def(
      "default_export_output",
      [](const std::string& format, const std::filesystem::path& base) {
        return default_export_output(export_format(format), base);
      },
      py::arg("format"), py::arg("base"),
      "The default output of `format` for a model at `base` (a path without extension): base + the first "
      "extension for a file, base_<name> for a folder, base for a prefix.");
  m.def("compare_results", &compare_results, py::arg("a"), py::arg("b"));
  m.def("read_result", &read_result, py::arg("path"), "Reads a result JSON (nodes, times, temperatures).");

  // decimation/decimate_nodes.h
  m.def("decimate_nodes", &decimate_nodes, py::arg("mesh"), py::arg("target_ratio_per_node"),
        py::arg("options") = DecimationOptions{}, release{},
        "Node-preserving decimation; target_ratio_per_node = fraction of each node's faces to remove.");
  m.def("decimate_to_global_ratio", &decimate_to_global_ratio, py::arg("mesh"), py::arg("global_ratio"),
        py::arg("options") = DecimationOptions{}, py::arg("max_rounds") = 3, release{},
        "Decimation to a global ratio of removed faces with the paper's per-node rule.");

  // reduction/reduce_model.h, report/reduction_report.h
  m.def(
      "reduce_model",
      [](const ThermalModel& model, const ReduceSettings& settings, bool force) {
        refuse_costly_run(check_simulation_cost(model, settings.reference.simulation, settings.extra_cases), force,
                          kForceHint);
        py::gil_scoped_release unlocked;
        return reduce_model(model, settings);
      },
      py::arg("model"), py::arg("settings") = ReduceSettings{}, py::arg("force") = false,
      "Simulation-driven reduction (`thermodec reduce`): as few faces as the temperature tolerance allows; "
      "force as for simulate_model.");
  m.def(
      "reduce_with_node_merging",
      [](const ThermalModel& model, const ReduceSettings& settings, const NodeMergeSettings& merge, bool force) {
        refuse_costly_run(check_simulation_cost(model, settings.reference.simulation, settings.extra_cases), force,
                          kForceHint);
        py::gil_scoped_release unlocked;
        return reduce_with_node_merging(model, settings, merge);
      },
      py::arg("model"), py::arg("settings") = ReduceSettings{}, py::arg("merge") = NodeMergeSettings{},
      py::arg("force") = false,
      "`thermodec reduce --merge-nodes`: nodes merged as well as decimated under the one tolerance; the "
      "reduced model carries the node map; force as for simulate_model. Raises InvalidInput (e.g. a keep "
      "pattern matching no node).");
  m.def("apply_large_model_sweep", &apply_large_model_sweep, py::arg("model"), py::arg("settings"),
        "Model files over 2000 faces: the sweep on halving face counts `thermodec reduce` uses (in place).");
  m.def("reduction_report", [](const ReductionRun& run) {
        return py::module_::import("json").attr("loads")(reduction_report_json(run).dump());
      }, py::arg("run"), "report.json content as Python objects");
  m.def("write_reduction_outputs", &write_reduction_outputs, py::arg("run"), py::arg("out_dir"),
        py::arg("protected_inputs") = std::vector<std::filesystem::path>{}, py::arg("plots") = true, release{},
        "Writes model.json + reduced.obj, report.json and plots into out_dir; returns plot warnings.");
  m.def("reduction_summary", &reduction_summary, py::arg("run"));

  // nodes/automatic_nodes.h
  m.def("assign_automatic_nodes", &assign_automatic_nodes, py::arg("mesh"),
        py::arg("options") = AutomaticNodeOptions{}, release{},
        "Overwrites mesh.face_node and mesh.node_names with an automatic nodal breakdown.");
}

}  // namespace

PYBIND11_MODULE(thermodec, m) {
  m.doc() = "thermodec core: thermal mesh reduction for spacecraft radiative analysis (SI units)";
  bind_errors(m);
  bind_mesh(m);
  bind_model(m);
  bind_results(m);
  bind_reduction(m);
  bind_functions(m);
}
