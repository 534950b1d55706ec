// One name for one thing across commands: -o/--output, --rays, repair's --weld-fraction (kelvin
// stays --tolerance's meaning), the export formats of the core's table, and `info --json`'s
// environment in the model file's own keys.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/cli_run.h"
#include "thermodec/exchange/export_formats.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/nodes/model_sections.h"

namespace fs = std::filesystem;

namespace {

using namespace thermodec::test;

const fs::path kData = THERMODEC_TEST_DATA_DIR;
const fs::path kSatellite = fs::path(THERMODEC_SOURCE_DIR) / "sample_models/satellite/model.json";

}  // namespace

TEST(CliConsistency, reduce_writes_to_output_and_takes_rays_as_the_other_commands) {
  auto d = temp_dir("reduce_output");
  const CliRun r = run_cli("reduce " + q(kData / "example_model.json") +
                               " --prediction-targets 1 --no-plots --quiet --rays 1000 --output " + q(d / "out"), d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "out" / "model.json"));
  EXPECT_TRUE(fs::exists(d / "out" / "report.json"));
  for (const char* command : {"reduce", "simulate", "export", "viewfactors", "external"}) {
    const CliRun help = run_cli(std::string(command) + " --help", d);
    EXPECT_TRUE(has(help.out, "--rays,--rays-per-face")) << command << "\n" << help.out;
  }
  const CliRun help = run_cli("reduce --help", d);
  EXPECT_TRUE(has(help.out, "-o,--output,--out")) << help.out;
}

TEST(CliConsistency, repair_takes_weld_fraction_and_warns_on_the_old_tolerance_name) {
  auto d = temp_dir("repair_weld");
  const CliRun now = run_cli("repair " + q(kData / "satellite.obj") + " -o " + q(d / "a.obj") + " --weld-fraction 1e-6", d);
  ASSERT_EQ(now.exit_code, 0) << now.err;
  EXPECT_FALSE(has(now.err, "deprecated")) << now.err;
  const CliRun old = run_cli("repair " + q(kData / "satellite.obj") + " -o " + q(d / "b.obj") + " --tolerance 1e-6", d);
  ASSERT_EQ(old.exit_code, 0) << old.err;
  EXPECT_TRUE(has(old.err, "--tolerance is deprecated, use --weld-fraction")) << old.err;
  EXPECT_EQ(read_text(d / "a.obj"), read_text(d / "b.obj"));
  const CliRun both = run_cli("repair " + q(kData / "satellite.obj") + " -o " + q(d / "c.obj") +
                                  " --tolerance 1e-6 --weld-fraction 1e-6", d);
  EXPECT_EQ(both.exit_code, 1);
  EXPECT_FALSE(has(run_cli("repair --help", d).out, "--tolerance"));
}

TEST(CliConsistency, export_offers_and_documents_every_row_of_the_format_table) {
  auto d = temp_dir("export_table");
  const CliRun help = run_cli("export --help", d);
  ASSERT_EQ(help.exit_code, 0);
  for (const thermodec::ExportFormat& f : thermodec::export_formats()) {
    EXPECT_TRUE(has(help.out, "  " + f.name + " ")) << f.name << "\n" << help.out;
    EXPECT_TRUE(has(help.out, f.help.substr(0, f.help.find('\n')))) << f.name;
  }
  const CliRun bad = run_cli("export " + q(kData / "example_model.json") + " --format esatn -o " + q(d / "x.d"), d);
  EXPECT_EQ(bad.exit_code, 1);
  for (const std::string& name : thermodec::export_format_names()) EXPECT_TRUE(has(bad.err, name)) << bad.err;
}

TEST(CliConsistency, info_json_environment_and_analysis_paste_back_into_a_model_file) {
  auto d = temp_dir("info_paste");
  for (const fs::path& model : {kSatellite, kData / "example_model.json"}) {
    const CliRun r = run_cli("info " + q(model) + " --json " + q(d / "info.json"), d);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto info = nlohmann::json::parse(read_text(d / "info.json"));
    auto pasted = nlohmann::json::parse(read_text(model));
    pasted["mesh"] = (model.parent_path() / pasted["mesh"].get<std::string>()).string();
    pasted["environment"] = info["environment"];
    pasted["analysis"] = info["analysis"];
    write_text(d / "pasted.json", pasted.dump(2));
    const thermodec::ThermalModel a = thermodec::load_model(model), b = thermodec::load_model(d / "pasted.json");
    EXPECT_TRUE(a.environment.type == b.environment.type && a.environment.altitude_km == b.environment.altitude_km &&
                a.environment.inclination_deg == b.environment.inclination_deg &&
                a.environment.raan_deg == b.environment.raan_deg && a.environment.day_of_year == b.environment.day_of_year &&
                a.environment.attitude == b.environment.attitude && a.environment.albedo == b.environment.albedo &&
                a.environment.earth_ir_flux_W_per_m2 == b.environment.earth_ir_flux_W_per_m2 &&
                a.environment.solar_flux_W_per_m2 == b.environment.solar_flux_W_per_m2 &&
                a.environment.sun_direction == b.environment.sun_direction)
        << model << "\n" << info["environment"].dump();
    EXPECT_TRUE(a.analysis.type == b.analysis.type && a.analysis.steps_per_orbit == b.analysis.steps_per_orbit &&
                a.analysis.orbits == b.analysis.orbits && a.analysis.time_tolerance_K == b.analysis.time_tolerance_K)
        << model;
    // Whatever the sections hold, the model file's spelling of them reads back the same.
    EXPECT_EQ(thermodec::environment_json(a.environment), thermodec::environment_json(b.environment)) << model;
  }
}
