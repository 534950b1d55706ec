// The table of export formats (exchange/export_formats.h): a trial format added by one writer and
// one row is offered, checked and written by export_model like the built-in ones.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "common/scratch_dir.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/exchange/export_model.h"
#include "thermodec/nodes/load_model.h"

namespace fs = std::filesystem;
using namespace thermodec;

namespace {

const fs::path kExample = fs::path(THERMODEC_TEST_DATA_DIR) / "example_model.json";

// --- The trial format: one writer ... ---------------------------------------------------------
// One line per node: name and temperature at the last time [K].
std::vector<fs::path> write_node_temperatures(const fs::path& out, const ExportInput& in) {
  std::ostringstream text;
  text.precision(17);
  const Eigen::MatrixXd& t_K = in.network->temperature_K;  // N x S
  for (size_t i = 0; i < in.model.nodes.size(); ++i)
    text << in.model.nodes[i].name << " " << t_K(Eigen::Index(i), t_K.cols() - 1) << "\n";
  write_text_atomically(out, text.str(), in.protected_inputs);
  return {out};
}

// --- ... and one row. -----------------------------------------------------------------------------
ExportFormat trial_row() {
  return {"trial", "Node temperatures", {".tnodes"}, true, ExportOutput::file, true,
          "one line per node: name, temperature [K] at the last time", &write_node_temperatures, nullptr};
}

// Adds the trial row once per test process (the table is process-wide).
const ExportFormat& trial_format() {
  static const bool added = [] {
    add_export_format(trial_row());
    return true;
  }();
  (void)added;
  return export_format("trial");
}

ThermalModel quick_example() {
  ThermalModel m = load_model(kExample);
  m.radiation.rays_per_face = 200;
  return m;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(ExportFormats, the_built_in_table_lists_the_five_formats_in_menu_order_with_writers) {
  const std::vector<std::string> names = export_format_names();
  ASSERT_GE(names.size(), 5u);
  const std::vector<std::string> first(names.begin(), names.begin() + 5);
  EXPECT_EQ(first, (std::vector<std::string>{"nastran", "esatan", "sinda", "vtk", "csv"}));
  for (const ExportFormat& f : export_formats()) {
    EXPECT_TRUE(f.write) << f.name;
    EXPECT_FALSE(f.title.empty() || f.help.empty() || f.extensions.empty()) << f.name;
  }
  EXPECT_FALSE(export_format("nastran").needs_simulation);
  EXPECT_EQ(export_format("vtk").output, ExportOutput::folder);
  EXPECT_EQ(default_export_output(export_format("esatan"), "dir/sat"), fs::path("dir/sat.d"));
  EXPECT_EQ(default_export_output(export_format("vtk"), "dir/sat"), fs::path("dir/sat_vtk"));
  EXPECT_EQ(default_export_output(export_format("csv"), "dir/sat"), fs::path("dir/sat"));
}

TEST(ExportFormats, an_unknown_name_is_refused_naming_every_choice) {
  try {
    export_format("esatn");
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    for (const std::string& name : export_format_names()) EXPECT_NE(std::string(e.what()).find(name), std::string::npos);
  }
}

TEST(ExportFormats, a_trial_format_is_one_writer_and_one_row_and_export_model_writes_it) {
  const ExportFormat& trial = trial_format();
  EXPECT_EQ(export_format_names().back(), "trial");
  EXPECT_NE(export_format_choices().find("or trial"), std::string::npos) << export_format_choices();
  EXPECT_EQ(default_export_output(trial, "dir/sat"), fs::path("dir/sat.tnodes"));

  const fs::path d = thermodec::test::scratch_dir("thermodec_test_export_formats", "trial");
  const ThermalModel model = quick_example();
  const fs::path out = d / "example.tnodes";
  ExportSettings settings;
  settings.protected_inputs = {kExample};
  const std::vector<fs::path> files = export_model(model, "trial", out, "example", settings);
  ASSERT_EQ(files, std::vector<fs::path>{out});
  // The writer saw the simulated network: one line per node with a temperature.
  std::istringstream lines(read_text(out));
  std::set<std::string> names;
  std::string name;
  double t_K = 0.0;
  while (lines >> name >> t_K) {
    names.insert(name);
    EXPECT_GT(t_K, 3.0) << name;
  }
  EXPECT_EQ(names, (std::set<std::string>{"body_px", "radiator"}));

  // The row's extensions are checked before the simulation, like NASTRAN's; a folder is refused.
  EXPECT_THROW(export_model(model, "trial", d / "example.txt", "example", settings), InvalidInput);
  EXPECT_THROW(export_model(model, "trial", d, "example", settings), InvalidInput);
  EXPECT_FALSE(fs::exists(d / "example.txt"));
}

TEST(ExportFormats, rows_with_a_taken_or_bad_name_or_no_writer_are_refused) {
  trial_format();
  EXPECT_THROW(add_export_format(trial_row()), InvalidInput);  // taken
  ExportFormat bad = trial_row();
  bad.name = "Bad Name";
  EXPECT_THROW(add_export_format(bad), InvalidInput);
  bad.name = "nowriter";
  bad.write = nullptr;
  EXPECT_THROW(add_export_format(bad), InvalidInput);
  bad = trial_row();
  bad.name = "noextension";
  bad.extensions.clear();
  EXPECT_THROW(add_export_format(bad), InvalidInput);
}
