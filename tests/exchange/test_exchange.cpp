// Exchange formats: NASTRAN bulk data in and out, ESATAN-TMS and SINDA/FLUINT networks read
// back and solved again, VTK and CSV files, and the CLI's `export` contract.
#include <unistd.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "common/cli_run.h"
#include "common/scratch_dir.h"
#include "network_readers.h"
#include "thermodec/common/errors.h"
#include "thermodec/exchange/exported_network.h"
#include "thermodec/exchange/write_csv_tables.h"
#include "thermodec/exchange/write_esatan_network.h"
#include "thermodec/exchange/write_nastran_bulk.h"
#include "thermodec/exchange/write_sinda_network.h"
#include "thermodec/exchange/write_vtk_series.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace fs = std::filesystem;
using namespace thermodec;

namespace {

const fs::path kSource = THERMODEC_SOURCE_DIR;
const fs::path kSample = kSource / "sample_models/satellite/model.json";

fs::path temp_dir(const std::string& name) { return thermodec::test::scratch_dir("thermodec_test_exchange", name); }

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

// The sample satellite at a small ray count (the exchange is exact whatever the sampling), one
// node made arithmetic (C = 0) so that every node kind of the formats is exercised.
struct Simulated {
  ThermalModel model;
  NodeCouplings couplings;
  SimulationResult result;
};

Simulated simulate_small(const fs::path& path, bool arithmetic_boom) {
  Simulated s;
  s.model = load_model(path);
  s.model.radiation.rays_per_face = 300;
  s.model.radiation.min_rays_per_node = 0;
  for (auto& n : s.model.nodes)
    if (arithmetic_boom && n.name == "boom") n.capacitance_J_per_K = 0.0;
  ModelSimulationSettings settings;
  settings.loads.sun_rays_per_face = 64;
  settings.loads.earth_rays_per_face = 64;
  s.result = simulate_model(s.model, settings, &s.couplings);
  return s;
}

const Simulated& sample_transient() {
  static const Simulated s = simulate_small(kSample, true);
  return s;
}

// Solves a network read back from a file the way `simulate` solves the model.
Eigen::MatrixXd solve(const exchange_test::ReadNetwork& r, int orbits) {
  if (!r.transient) return steady_state(r.network, r.external_W.col(0)).temperature_K;
  TransientSettings ts;
  ts.max_orbits = orbits;
  // Backward Euler on the table points (positions and both sides of each eclipse switch).
  return periodic_transient_on_grid(r.network, r.external_W, r.times_s, r.period_s, ts).temperature_K;
}

double max_abs_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  EXPECT_EQ(a.rows(), b.rows());
  EXPECT_EQ(a.cols(), b.cols());
  if (a.rows() != b.rows() || a.cols() != b.cols()) return 1e300;
  return (a - b).cwiseAbs().maxCoeff();
}

using thermodec::test::CliRun;
using thermodec::test::q;
using thermodec::test::run_cli;

// `thermodec info` lines that describe the geometry and the nodes (faces, areas), not the paths.
std::string info_geometry(const std::string& out) {
  std::istringstream in(out);
  std::string kept, line;
  bool nodes = false;
  while (std::getline(in, line)) {
    if (line.rfind("faces", 0) == 0 || line.rfind("vertices", 0) == 0 || line.rfind("area", 0) == 0) kept += line + "\n";
    if (line.rfind("nodes", 0) == 0) nodes = true;
    if (nodes) kept += line + "\n";
  }
  return kept;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no InvalidInput thrown)";
}

}  // namespace

// The 0.01 K bound: a file that lost a node, a conductor or a load step moves some node by far
// more (a 1 W load on the 900 J/K yoke alone moves it by > 0.1 K).
constexpr double kSameTemperatureK = 0.01;

// The network thermodec exported, solved as the read-back files are (backward Euler on the
// table points): the reference for "every node, conductor and load reached the file". The
// comparison with simulate's own, time-converged transient, integrating each file as its
// tool does, is tests/exchange/deck_round_trip.py.
Eigen::MatrixXd solve_exported(const ExportedNetwork& e, int orbits) {
  exchange_test::ReadNetwork r;
  r.network = e.network;
  r.transient = e.transient;
  r.period_s = e.period_s;
  r.times_s = e.transient ? e.table_times_s : e.times_s;
  r.external_W = e.transient ? e.table_external_W() : e.external_W();
  return solve(r, orbits);
}

TEST(ExchangeEsatan, transient_network_read_back_and_solved_matches_the_exported_network_within_0_01_K) {
  const Simulated& s = sample_transient();
  ASSERT_TRUE(s.result.transient);
  const auto d = temp_dir("esatan_transient");
  const ExportedNetwork e = exported_network(s.model, s.couplings, s.result, "sample");
  write_esatan_network(d / "sat.d", e);
  const auto r = exchange_test::read_esatan((d / "sat.d").string());
  EXPECT_TRUE(r.transient);
  EXPECT_EQ(r.network.num_nodes(), static_cast<int>(s.model.nodes.size()));
  EXPECT_EQ(r.network.capacitance_J_per_K.minCoeff(), 0.0);  // the arithmetic node came through
  const Eigen::MatrixXd reference = solve_exported(e, s.model.analysis.orbits);
  EXPECT_LT(max_abs_difference(solve(r, s.model.analysis.orbits), reference), kSameTemperatureK);
  // The check has teeth: the same file without the wing's coupling to space is far off.
  std::string text = exchange_test::slurp((d / "sat.d").string());
  const std::size_t at = text.find("GR(8, 99999)");
  ASSERT_NE(at, std::string::npos);
  text.erase(at, text.find('\n', at) - at + 1);
  write(d / "lost.d", text);
  const auto lost = exchange_test::read_esatan((d / "lost.d").string());
  EXPECT_GT(max_abs_difference(solve(lost, s.model.analysis.orbits), reference), 1.0);
}

TEST(ExchangeSinda, transient_network_read_back_and_solved_matches_the_exported_network_within_0_01_K) {
  const Simulated& s = sample_transient();
  const auto d = temp_dir("sinda_transient");
  const ExportedNetwork e = exported_network(s.model, s.couplings, s.result, "sample");
  write_sinda_network(d / "sat.inp", e);
  const auto r = exchange_test::read_sinda((d / "sat.inp").string());
  EXPECT_TRUE(r.transient);
  EXPECT_EQ(r.network.num_nodes(), static_cast<int>(s.model.nodes.size()));
  EXPECT_LT(max_abs_difference(solve(r, s.model.analysis.orbits), solve_exported(e, s.model.analysis.orbits)),
            kSameTemperatureK);
}

TEST(ExchangeNetworks, steady_model_with_a_boundary_node_read_back_matches_simulate_within_0_01_K) {
  const Simulated s = simulate_small(kSource / "tests/data/example_model.json", false);
  ASSERT_FALSE(s.result.transient);
  const auto d = temp_dir("steady");
  const ExportedNetwork e = exported_network(s.model, s.couplings, s.result, "example");
  write_esatan_network(d / "m.d", e);
  write_sinda_network(d / "m.inp", e);
  for (const auto& r : {exchange_test::read_esatan((d / "m.d").string()), exchange_test::read_sinda((d / "m.inp").string())}) {
    EXPECT_FALSE(r.transient);
    int fixed = 0;
    for (int i = 0; i < r.network.num_nodes(); ++i) fixed += r.network.is_fixed(i);
    EXPECT_EQ(fixed, 1);  // the radiator, a boundary node
    EXPECT_LT(max_abs_difference(solve(r, 1), s.result.temperature_K), kSameTemperatureK);
  }
}

TEST(ExchangeNastran, exported_sample_reads_back_with_the_same_faces_nodes_areas_and_coatings) {
  const ThermalModel m = load_model(kSample);
  const auto d = temp_dir("nastran_sample");
  write_nastran_bulk(d / "sat.bdf", m);
  const ThermalModel b = load_model(d / "sat.bdf");
  ASSERT_EQ(b.mesh.num_faces(), m.mesh.num_faces());
  ASSERT_EQ(b.mesh.num_vertices(), m.mesh.num_vertices());
  ASSERT_EQ(b.nodes.size(), m.nodes.size());
  // GRID* keeps 15-16 significant digits: areas agree to ~1e-14 relative.
  const Eigen::VectorXd area_m = face_areas(m.mesh.V, m.mesh.F), area_b = face_areas(b.mesh.V, b.mesh.F);
  for (int f = 0; f < m.mesh.num_faces(); ++f) {
    ASSERT_NEAR(area_b[f], area_m[f], 1e-12 * area_m[f]) << "face " << f;
    ASSERT_EQ(b.nodes[b.mesh.face_node[f]].name, m.nodes[m.mesh.face_node[f]].name) << "face " << f;
    const Material& fm = m.materials[m.mesh.face_material[f]];
    const Material& fb = b.materials[b.mesh.face_material[f]];
    ASSERT_EQ(fb.name, fm.name);
    ASSERT_EQ(fb.absorptivity, fm.absorptivity);
    ASSERT_EQ(fb.emissivity, fm.emissivity);
    ASSERT_EQ(b.mesh.is_two_sided(f), m.mesh.is_two_sided(f)) << "face " << f;
  }
}

TEST(ExchangeNastran, small_field_free_field_and_quads_are_read_as_triangles_per_property) {
  const auto d = temp_dir("nastran_dialects");
  write(d / "q.bdf",
        "SOL 101\nCEND\nBEGIN BULK\n"
        "$ a unit square as one CQUAD4 (small field) and a triangle in free field\n"
        "GRID    1               0.      0.      0.\n"
        "GRID    2               1.      0.      0.\n"
        "GRID    3               1.      1.      0.\n"
        "GRID,4,,0.,1.,0.\n"
        "GRID    5               2.      0.      0.\n"
        "CQUAD4  10      7       1       2       3       4\n"
        "CTRIA3,11,8,2,5,3\n"
        "PSHELL  7       3       .001\n"
        "RADM    3       .25     .9\n"
        "CBAR    20      1       1       2       0.      0.      1.\n"
        "CONM2   30      1               1.5-3\n"
        "ENDDATA\n");
  const ThermalModel m = load_model(d / "q.bdf");
  ASSERT_EQ(m.mesh.num_faces(), 3);
  EXPECT_EQ(m.nodes.size(), 2u);
  EXPECT_EQ(m.nodes[0].name, "PID7");
  EXPECT_EQ(m.nodes[1].name, "PID8");
  EXPECT_NEAR(face_areas(m.mesh.V, m.mesh.F).sum(), 1.5, 1e-15);
  const Material& coat = m.materials[m.mesh.face_material[0]];
  EXPECT_EQ(coat.name, "MAT3");
  EXPECT_EQ(coat.absorptivity, 0.25);
  EXPECT_EQ(coat.emissivity, 0.9);
}

TEST(ExchangeNastran, element_naming_a_missing_grid_is_refused_with_file_line_and_card) {
  const auto d = temp_dir("nastran_missing_grid");
  write(d / "m.bdf", "BEGIN BULK\nGRID    1               0.      0.      0.\nGRID    2               1.      0.      0.\n"
                     "CTRIA3  5       1       1       2       99\nENDDATA\n");
  const std::string e = error_of([&] { load_model(d / "m.bdf"); });
  EXPECT_NE(e.find("m.bdf:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("CTRIA3 5"), std::string::npos) << e;
  EXPECT_NE(e.find("GRID 99"), std::string::npos) << e;
}

TEST(ExchangeNastran, non_numeric_field_is_refused_with_file_line_card_and_field) {
  const auto d = temp_dir("nastran_bad_number");
  write(d / "m.bdf", "BEGIN BULK\nGRID    1               0.      0.      0.\nGRID    2               1.      abc     0.\nENDDATA\n");
  const std::string e = error_of([&] { load_model(d / "m.bdf"); });
  EXPECT_NE(e.find("m.bdf:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("GRID 2"), std::string::npos) << e;
  EXPECT_NE(e.find("X2"), std::string::npos) << e;
  EXPECT_NE(e.find("'abc'"), std::string::npos) << e;
}

TEST(ExchangeNastran, grid_in_a_local_coordinate_system_is_refused) {
  const auto d = temp_dir("nastran_cp");
  write(d / "m.bdf", "BEGIN BULK\nGRID    1       4       0.      0.      0.\nENDDATA\n");
  const std::string e = error_of([&] { load_model(d / "m.bdf"); });
  EXPECT_NE(e.find("m.bdf:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("coordinate system"), std::string::npos) << e;
}

TEST(ExchangeVtk, series_has_one_step_per_time_and_every_face_in_each) {
  const Simulated& s = sample_transient();
  const auto d = temp_dir("vtk");
  const fs::path pvd = write_vtk_series(d, "sat", s.model, exported_network(s.model, s.couplings, s.result, "sample"));
  const std::string collection = exchange_test::slurp(pvd.string());
  const int steps = static_cast<int>(s.result.times_s.size());
  int datasets = 0;
  for (std::size_t p = 0; (p = collection.find("<DataSet", p)) != std::string::npos; ++p) ++datasets;
  EXPECT_EQ(datasets, steps);
  const std::string first = exchange_test::slurp((d / "sat_0000.vtu").string());
  EXPECT_NE(first.find("NumberOfCells=\"" + std::to_string(s.model.mesh.num_faces()) + "\""), std::string::npos);
  EXPECT_NE(first.find("Name=\"temperature_K\""), std::string::npos);
  EXPECT_NE(first.find("Name=\"absorbed_flux_W_per_m2\""), std::string::npos);
}

TEST(ExchangeCsv, coupling_table_lists_every_nonzero_pair_once_with_its_unit) {
  const Simulated& s = sample_transient();
  const auto d = temp_dir("csv");
  const ExportedNetwork e = exported_network(s.model, s.couplings, s.result, "sample");
  const auto files = write_csv_tables(d / "sat", e);
  ASSERT_EQ(files.size(), 4u);
  std::istringstream in(exchange_test::slurp(files[1].string()));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "from,to,type,value,unit");
  int gl = 0, gr = 0;
  while (std::getline(in, line)) (line.find(",GL,") != std::string::npos ? gl : gr)++;
  int expect_gl = 0, expect_gr = 0;
  const int n = e.num_nodes();
  for (int i = 0; i < n; ++i) {
    expect_gr += e.network.to_space_couplings_m2[i] != 0.0;
    for (int j = i + 1; j < n; ++j) {
      expect_gl += e.network.conductance_W_per_K(i, j) != 0.0;
      expect_gr += e.network.radiative_couplings_m2(i, j) != 0.0;
    }
  }
  EXPECT_EQ(gl, expect_gl);
  EXPECT_EQ(gr, expect_gr);
}

TEST(ExchangeCertificate, reduced_model_keeps_its_certificate_and_every_export_header_repeats_it) {
  const Simulated& s = sample_transient();
  const auto d = temp_dir("certificate");
  ThermalModel model = s.model;
  ModelCertificate c;
  c.original_model = kSample.string();
  c.original_sha256 = file_sha256(kSample.string());
  c.tolerance_K = 0.5;
  c.cases = {"model", "hot"};
  c.estimate_K = 0.38, c.standard_error_K = 0.0045, c.upper_bound_K = 0.394, c.confidence = 0.975;
  c.seeds = {1048577, 1048578};
  c.faces_before = 882, c.faces_after = 112;
  model.certificate = c;
  EXPECT_EQ(c.original_sha256.size(), 64u);
  save_model(model, d / "reduced.json", d / "reduced.obj");
  const ThermalModel back = load_model(d / "reduced.json");
  ASSERT_TRUE(back.certificate.has_value());
  EXPECT_EQ(certificate_lines(*back.certificate), certificate_lines(c));
  const ExportedNetwork e = exported_network(back, s.couplings, s.result, "reduced");
  write_esatan_network(d / "r.d", e);
  write_sinda_network(d / "r.inp", e);
  const auto csv = write_csv_tables(d / "r", e);
  write_nastran_bulk(d / "r.bdf", back);
  const std::string origin = "original model: " + kSample.string() + " (sha256 " + c.original_sha256 + ")";
  EXPECT_NE(exchange_test::slurp((d / "r.d").string()).find("# " + origin), std::string::npos);
  EXPECT_NE(exchange_test::slurp((d / "r.inp").string()).find("C " + origin), std::string::npos);
  EXPECT_NE(exchange_test::slurp(csv.back().string()).find("# " + origin), std::string::npos);
  const std::string bdf = exchange_test::slurp((d / "r.bdf").string());
  EXPECT_NE(bdf.find("$ original model: "), std::string::npos);
  EXPECT_LT(bdf.find("upper bound 0.394 K at 97.5 % confidence"), bdf.find("BEGIN BULK"));
  const CliRun info = run_cli("info " + q(d / "reduced.json"), d);
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("verified max |dT|: 0.38 +- 0.0045 K"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("verification seeds: 1048577 1048578"), std::string::npos) << info.out;
}

TEST(ExchangeCli, nastran_export_of_the_reduced_sample_reads_back_in_info_with_the_same_faces_nodes_and_areas) {
  const auto d = temp_dir("cli_reduced");
  const CliRun dec = run_cli("decimate " + q(kSample) + " --ratio 0.5 -o " + q(d / "reduced.json"), d);
  ASSERT_EQ(dec.exit_code, 0) << dec.err;
  const CliRun ex = run_cli("export " + q(d / "reduced.json") + " --format nastran -o " + q(d / "reduced.bdf"), d);
  ASSERT_EQ(ex.exit_code, 0) << ex.err;
  const CliRun a = run_cli("info " + q(d / "reduced.json"), d);
  const CliRun b = run_cli("info " + q(d / "reduced.bdf"), d);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(info_geometry(a.out).find("nodes"), std::string::npos) << a.out;
  EXPECT_EQ(info_geometry(b.out), info_geometry(a.out));
}

TEST(ExchangeCli, export_writes_all_five_formats_for_the_sample_and_its_reduced_model) {
  const auto d = temp_dir("cli_five_formats");
  const CliRun dec = run_cli("decimate " + q(kSample) + " --ratio 0.5 -o " + q(d / "reduced.json"), d);
  ASSERT_EQ(dec.exit_code, 0) << dec.err;
  struct Output {
    const char* format;
    const char* out;       // as given to -o
    const char* written;   // a file it must write (vtk: the series' collection)
  };
  const Output outputs[] = {{"nastran", ".bdf", ".bdf"}, {"esatan", ".d", ".d"}, {"sinda", ".inp", ".inp"},
                            {"vtk", "_vtk", "_vtk/@.pvd"}, {"csv", "", "_couplings.csv"}};
  for (const fs::path& model : {kSample, d / "reduced.json"}) {
    const std::string stem = model.stem().string(), tag = model == kSample ? "sample" : "reduced";
    for (const Output& o : outputs) {
      // Few rays: the test is about the files, not the accuracy of the couplings.
      const CliRun r = run_cli("export " + q(model) + " --format " + o.format + " -o " + q(d / (tag + o.out)) +
                                   " --rays 32 --noise-target 0 -q",
                               d);
      ASSERT_EQ(r.exit_code, 0) << o.format << " " << tag << ": " << r.err;
      std::string written = tag + o.written;
      if (const auto at = written.find('@'); at != std::string::npos) written.replace(at, 1, stem);
      EXPECT_GT(fs::file_size(d / written), 0u) << written;
    }
  }
}

// A BDF error through the CLI: one line on stderr naming the file, the line and the card; no
// output written.
void expect_bdf_refused(const std::string& name, const std::string& bulk, const std::vector<std::string>& says) {
  const auto d = temp_dir("cli_" + name);
  write(d / "m.bdf", bulk);
  const CliRun r = run_cli("export " + q(d / "m.bdf") + " --format nastran -o " + q(d / "out.bdf"), d);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  for (const auto& s : says) EXPECT_NE(r.err.find(s), std::string::npos) << "'" << s << "' not in: " << r.err;
  EXPECT_FALSE(fs::exists(d / "out.bdf"));
}

TEST(ExchangeCli, bdf_element_naming_a_missing_grid_is_refused_with_file_line_and_card) {
  expect_bdf_refused("missing_grid",
                     "BEGIN BULK\nGRID    1               0.      0.      0.\nGRID    2               1.      0.      0.\n"
                     "CTRIA3  5       1       1       2       99\nENDDATA\n",
                     {"m.bdf:4:", "CTRIA3 5", "GRID 99"});
}

TEST(ExchangeCli, bdf_non_numeric_field_is_refused_with_file_line_card_and_field) {
  expect_bdf_refused("bad_number",
                     "BEGIN BULK\nGRID    1               0.      0.      0.\nGRID    2               1.      abc     0.\nENDDATA\n",
                     {"m.bdf:3:", "GRID 2", "X2", "'abc'"});
}

TEST(ExchangeCli, unknown_format_is_a_usage_error_naming_the_choices) {
  const auto d = temp_dir("cli_format");
  const CliRun r = run_cli("export " + q(kSample) + " --format step -o " + q(d / "x.step"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("step"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nastran"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "x.step"));
}

TEST(ExchangeCli, output_onto_the_input_is_refused_before_any_work) {
  const auto d = temp_dir("cli_overwrite");
  fs::copy_file(kSource / "tests/data/example_model.json", d / "m.json");
  fs::copy_file(kSource / "tests/data/satellite.obj", d / "satellite.obj");
  const std::string before = exchange_test::slurp((d / "satellite.obj").string());
  const CliRun r = run_cli("export " + q(d / "m.json") + " --format esatan -o " + q(d / "satellite.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("overwrite the input"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("simulate"), std::string::npos) << "refused only after simulating: " << r.err;
  EXPECT_EQ(exchange_test::slurp((d / "satellite.obj").string()), before);
}

TEST(ExchangeCli, simulate_vtk_writes_a_series_beside_the_result) {
  const auto d = temp_dir("cli_simulate_vtk");
  const CliRun r = run_cli("simulate " + q(kSource / "tests/data/example_model.json") + " --noise-target 0 -q --vtk " +
                               q(d / "vtk"),
                           d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "vtk" / "example_model.pvd"));
  EXPECT_TRUE(fs::exists(d / "vtk" / "example_model_0000.vtu"));  // steady: one step
  EXPECT_FALSE(fs::exists(d / "vtk" / "example_model_0001.vtu"));
}

TEST(ExchangeNetworks, power_schedule_and_thermostat_reach_the_esatan_and_sinda_decks) {
  // schedule_doublets: each value held to 1 ms before the next time, the first repeated at P.
  const auto d = schedule_doublets({{0.0, 5.0}, {100.0, 45.0}}, 300.0);
  const double r = ExportedNetwork::kSwitchRamp_s;
  const std::vector<std::pair<double, double>> expected{{0.0, 5.0}, {100.0 - r, 5.0}, {100.0, 45.0}, {300.0 - r, 45.0}, {300.0, 5.0}};
  EXPECT_EQ(d, expected);
  ExportedNetwork e = exported_network(sample_transient().model, sample_transient().couplings, sample_transient().result, "sample");
  const int n = e.num_nodes();
  e.network.power_schedule_W.assign(n, {});
  e.network.power_schedule_W[12] = {{0.0, 5.0}, {0.5 * e.period_s, 45.0}};
  e.network.power_W[12] = 0.0;
  e.network.heaters = {{5, Thermostat{240.0, 245.0, 120.0}}};
  const auto dir = temp_dir("schedules");
  write_esatan_network(dir / "sat.d", e);
  const std::string esatan = exchange_test::slurp((dir / "sat.d").string());
  for (const char* line : {"QINT13(10) =", "      QI(13) = INTCY1(TIMEM, QINT13, PERIOD)", "HON6 = 240.0;", "HOF6 = 245.0;",
                           "HPW6 = 120.0;", "      IF (T(6) .LT. HON6) HTR6 = 1", "      IF (T(6) .GT. HOF6) HTR6 = 0",
                           "      IF (HTR6 .EQ. 1) QI(6) = QI(6) + HPW6"})
    EXPECT_NE(esatan.find(line), std::string::npos) << line;
  write_sinda_network(dir / "sat.inp", e);
  const std::string sinda = exchange_test::slurp((dir / "sat.inp").string());
  for (const char* line : {"      2013 = 0.0, 5.0", "      Q13 = D11CYL(TIMEN, A2013, ", "HEADER REGISTER DATA", "      HON6 = 240.0",
                           "      IF (T6 .LT. HON6) HTR6 = 1.0", "      Q6 = Q6 + HTR6 * HPW6"})
    EXPECT_NE(sinda.find(line), std::string::npos) << line;
  // A deck without schedules or heaters is written as before: none of these lines.
  const ExportedNetwork plain = exported_network(sample_transient().model, sample_transient().couplings, sample_transient().result, "sample");
  write_esatan_network(dir / "plain.d", plain);
  const std::string p = exchange_test::slurp((dir / "plain.d").string());
  EXPECT_EQ(p.find("QINT"), std::string::npos);
  EXPECT_EQ(p.find("HTR"), std::string::npos);
}
