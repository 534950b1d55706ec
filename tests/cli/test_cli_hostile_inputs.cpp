// Hostile and broken inputs and outputs: geometry whose areas overflow, names carrying terminal
// escapes, NASTRAN decks with duplicated or negative ids, outputs that are devices, FIFOs or
// have no extension, and symlinks planted at temporary names. Each is refused by name before any
// work (exit 1), never crashes, and never writes through a link.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <filesystem>
#include <string>

#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {

using namespace thermodec::test;

const fs::path kData = THERMODEC_TEST_DATA_DIR;

// A unit cube with corners at ±`c` as an OBJ (12 triangles).
std::string cube_obj(const std::string& c) {
  std::string s;
  for (int i = 0; i < 8; ++i)
    s += "v " + std::string(i & 1 ? "" : "-") + c + " " + (i & 2 ? "" : "-") + c + " " + (i & 4 ? "" : "-") + c + "\n";
  s += "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
  return s;
}

// The same cube as a NASTRAN deck (free field), coordinates written as `c` (e.g. "1.+308").
std::string cube_bdf(const std::string& c, const std::string& extra = "", bool enddata = true) {
  std::string s = "BEGIN BULK\n" + extra;
  for (int i = 0; i < 8; ++i)
    s += "GRID," + std::to_string(i + 1) + ",," + (i & 1 ? "" : "-") + c + "," + (i & 2 ? "" : "-") + c + "," +
         (i & 4 ? "" : "-") + c + "\n";
  const int f[12][3] = {{1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}, {1, 2, 6}, {1, 6, 5},
                        {3, 7, 8}, {3, 8, 4}, {1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}};
  for (int k = 0; k < 12; ++k)
    s += "CTRIA3," + std::to_string(k + 1) + ",1," + std::to_string(f[k][0]) + "," + std::to_string(f[k][1]) + "," +
         std::to_string(f[k][2]) + "\n";
  return s + (enddata ? "ENDDATA\n" : "");
}

bool has_control_bytes(const std::string& s) {
  for (unsigned char c : s)
    if ((c < 0x20 && c != '\n') || c == 0x7f) return true;
  return s.find("\xe2\x80\xae") != std::string::npos;
}

void expect_refused(const CliRun& r, const std::string& part) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, part)) << r.err;
  EXPECT_FALSE(has_control_bytes(r.err)) << r.err;
}

const char* const kFewRays = " --rays 20 --earth-rays 16 --sun-rays 16 --noise-target 0 ";

}  // namespace

TEST(CliHostileInputs, geometry_whose_areas_overflow_is_refused_by_info_and_simulate_alike) {
  auto d = temp_dir("overflow");
  write_text(d / "far.obj", "v 1e308 0 0\nv -1e308 0 0\nv 0 1e308 0\nf 1 2 3\n");
  write_text(d / "cube.obj", cube_obj("1e308"));
  write_text(d / "cube.bdf", cube_bdf("1.+308"));
  write_text(d / "big.obj", cube_obj("1e30"));  // areas finite in double, beyond the ray tracer's floats
  for (const char* name : {"far.obj", "cube.obj", "cube.bdf", "big.obj"}) {
    SCOPED_TRACE(name);
    expect_refused(run_cli("info " + q(d / name), d), std::string(name) + ": vertex 0");
    expect_refused(run_cli(std::string("simulate -q") + kFewRays + q(d / name), d), name);
  }
  // A model whose unit_scale carries the mesh beyond the range is refused too.
  write_text(d / "mm.obj", cube_obj("1e9"));
  write_text(d / "model.json", R"({"mesh": "mm.obj", "unit_scale": 1e4})");
  expect_refused(run_cli("info " + q(d / "model.json"), d), "unit_scale");
  write_text(d / "ok.obj", cube_obj("1e9"));
  EXPECT_EQ(run_cli("info " + q(d / "ok.obj"), d).exit_code, 0);
}

TEST(CliHostileInputs, names_with_terminal_escapes_are_refused_and_never_printed_raw) {
  auto d = temp_dir("escapes");
  write_text(d / "esc.bdf", cube_bdf("1.", "$ thermodec node 1 \x1b]0;owned\x07\x1b[2Jradiator\xe2\x80\xae\n"));
  expect_refused(run_cli("info " + q(d / "esc.bdf"), d), "control characters");
  write_text(d / "esc.obj", "g \x1b[31mred\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_refused(run_cli("info " + q(d / "esc.obj"), d), "control characters");
  // Binary bytes and a 1 MB field: the messages quote a short, escaped part.
  std::string binary = "GRID,1,,";
  for (int i = 0; i < 256; ++i) binary += static_cast<char>(i);
  write_text(d / "binary.bdf", cube_bdf("1.", binary + "\n" + std::string(1 << 20, 'Z') + ",1\n"));
  const CliRun r = run_cli("info " + q(d / "binary.bdf"), d);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(has_control_bytes(r.err)) << r.err;
  EXPECT_LT(r.err.size(), 2000u);
  std::string junk_cards = cube_bdf("1.");
  junk_cards.insert(junk_cards.find("ENDDATA"), std::string(1 << 20, 'Q') + ",1\n\x1b[2J,1\n");
  write_text(d / "junk.bdf", junk_cards);
  const CliRun w = run_cli("info " + q(d / "junk.bdf"), d);
  EXPECT_EQ(w.exit_code, 0) << w.err;
  EXPECT_TRUE(has(w.err, "skipped cards")) << w.err.substr(0, 300);
  EXPECT_FALSE(has_control_bytes(w.err));
  EXPECT_LT(w.err.size(), 2000u);
}

TEST(CliHostileInputs, nastran_duplicate_element_ids_and_negative_grids_are_refused_a_cut_deck_warns) {
  auto d = temp_dir("bdf_ids");
  std::string dup = cube_bdf("1.");
  dup.insert(dup.find("ENDDATA"), "CTRIA3,3,1,1,2,6\n");
  write_text(d / "dup.bdf", dup);
  expect_refused(run_cli("info " + q(d / "dup.bdf"), d), "element 3 is defined twice");
  std::string quad = cube_bdf("1.");
  quad.insert(quad.find("ENDDATA"), "CQUAD4,12,1,1,2,6,5\n");
  write_text(d / "dupquad.bdf", quad);
  expect_refused(run_cli("info " + q(d / "dupquad.bdf"), d), "element 12 is defined twice");
  std::string negative = cube_bdf("1.");
  negative.replace(negative.find("GRID,1,"), 7, "GRID,-1,");
  write_text(d / "negative.bdf", negative);
  expect_refused(run_cli("info " + q(d / "negative.bdf"), d), "must be a positive integer");
  write_text(d / "cut.bdf", cube_bdf("1.", "", false));
  const CliRun cut = run_cli("info " + q(d / "cut.bdf"), d);
  EXPECT_EQ(cut.exit_code, 0) << cut.err;
  EXPECT_TRUE(has(cut.err, "no ENDDATA")) << cut.err;
}

TEST(CliHostileOutputs, export_refuses_fifos_devices_and_extensionless_outputs_before_any_work) {
  auto d = temp_dir("export_kinds");
  const std::string model = q(kData / "example_model.json");
  ASSERT_EQ(::mkfifo((d / "pipe.bdf").c_str(), 0600), 0);
  expect_refused(run_cli("export " + model + " --format nastran -o " + q(d / "pipe.bdf"), d, "timeout 20"),
                 "not a regular file");
  EXPECT_TRUE(fs::is_fifo(d / "pipe.bdf"));
  ASSERT_EQ(::mkfifo((d / "pipe.d").c_str(), 0600), 0);
  const CliRun esatan = run_cli("export " + model + " --format esatan -o " + q(d / "pipe.d"), d, "timeout 20");
  expect_refused(esatan, "not a regular file");
  EXPECT_FALSE(has(esatan.err, "estimated cost")) << esatan.err;  // refused before the simulation's estimate
  if (::mknod((d / "null.bdf").c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0) {
    expect_refused(run_cli("export " + model + " --format nastran -o " + q(d / "null.bdf"), d), "not a regular file");
    EXPECT_TRUE(fs::is_character_file(d / "null.bdf"));
  }
  expect_refused(run_cli("export " + model + " --format nastran -o " + q(d / "noext"), d), "extension");
  expect_refused(run_cli("export " + model + " --format sinda -o " + q(d / "noext"), d), "extension");
  EXPECT_FALSE(fs::exists(d / "noext"));
  write_text(d / "afile", "x");
  const CliRun folder = run_cli("export " + model + " --format esatan -o " + q(d / "afile" / "m.d"), d);
  expect_refused(folder, "is not a folder");
  EXPECT_FALSE(has(folder.err, "estimated cost")) << folder.err;
}

TEST(CliHostileOutputs, a_link_planted_at_the_old_temporary_name_is_never_followed) {
  auto d = temp_dir("planted");
  write_text(d / "victim.txt", "precious");
  fs::create_directories(d / "shared");
  // The shell's pid becomes thermodec's (exec): the link sits at the name older versions used.
  const std::string shared = (d / "shared").string();
  const CliRun r = run_cli(std::string("simulate -q") + kFewRays + q(kData / "example_model.json") + " --json " +
                               q(d / "shared" / "r.json"),
                           d, "sh -c 'ln -s ../victim.txt \"" + shared + "/.r.json.tmp$$\"; exec \"$0\" \"$@\"'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_text(d / "victim.txt"), "precious");
  EXPECT_TRUE(has(read_text(d / "shared" / "r.json"), "temperatures_K")) << read_text(d / "shared" / "r.json");
}

TEST(CliHostileOutputs, an_existing_private_output_stays_private) {
  auto d = temp_dir("private_out");
  write_text(d / "r.json", "{}");
  fs::permissions(d / "r.json", fs::perms::owner_read | fs::perms::owner_write);
  const CliRun r = run_cli(std::string("simulate -q") + kFewRays + q(kData / "example_model.json") + " --json " + q(d / "r.json"),
                           d, "umask 022;");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(fs::status(d / "r.json").permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
}

TEST(CliHostileInputs, decimate_refuses_a_fifo_as_node_ratios) {
  auto d = temp_dir("ratios_fifo");
  ASSERT_EQ(::mkfifo((d / "ratios.json").c_str(), 0600), 0);
  const CliRun r = run_cli("decimate " + q(kData / "example_model.json") + " --node-ratios " + q(d / "ratios.json") +
                               " -o " + q(d / "half.json"),
                           d, "timeout 20");
  expect_refused(r, "not a regular file");
}
