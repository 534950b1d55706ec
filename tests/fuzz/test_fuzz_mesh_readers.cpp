// Mutation fuzzing of the mesh readers (mesh/io.h, mesh/format_bdf.h) in-process: every input
// is read as a valid mesh or refused with a thermodec::Error (fuzz_harness.h). Each corpus
// holds the formats' variants (ascii and binary, groups, materials, two-sided faces, the NASTRAN
// field layouts); every 8th input is also loaded as a bare-mesh model (cleanup, automatic nodes,
// RADM coatings).
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "fuzz/fuzz_harness.h"
#include "mesh/mesh_test_util.h"
#include "thermodec/mesh/format_bdf.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;
namespace fs = std::filesystem;

namespace {

const fs::path kData = THERMODEC_TEST_DATA_DIR;
const fs::path kSample = fs::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite";

// Inputs per reader: 1 to 3 s each in a Release build on one core (files in /dev/shm).
constexpr int kIterations = 30000;

// The bytes write_mesh produces for `mesh` as `name` (extension = format).
std::string written(const Mesh& mesh, const fs::path& dir, const std::string& name, bool binary) {
  MeshWriteOptions o;
  o.binary = binary;
  write_mesh(dir / name, mesh, o);
  return fuzz::read_bytes(dir / name);
}

// The reader of one format: read_mesh, and every 8th input load_model as a bare mesh.
fuzz::Reader mesh_reader() {
  return [](const fs::path& path, int iteration) {
    MeshReadReport report;
    MeshReadOptions options;
    options.drop_degenerate_faces = iteration % 2 == 0;
    const Mesh mesh = read_mesh(path, options, report);
    std::string problem = fuzz::mesh_problem(mesh);
    if (problem.empty() && iteration % 8 == 3) {
      const ThermalModel model = load_model(path, ModelLoadOptions{});
      problem = fuzz::mesh_problem(model.mesh);
      for (int f = 0; problem.empty() && f < model.mesh.num_faces(); ++f)
        if (model.mesh.face_node[f] < 0 || model.mesh.face_node[f] >= static_cast<int>(model.nodes.size()))
          problem = "model face " + std::to_string(f) + " has no node";
    }
    return problem;
  };
}

// The corpus is made of valid files: each reads as it is.
void expect_corpus_reads(const std::vector<std::string>& corpus, const fs::path& dir, const std::string& file_name,
                         const fuzz::Reader& reader) {
  for (const std::string& failure : fuzz::corpus_failures(corpus, dir, file_name, reader)) ADD_FAILURE() << failure;
}

void expect_clean(const fuzz::FuzzRun& run) {
  EXPECT_TRUE(run.failures.empty()) << fuzz::report(run);
  EXPECT_GT(run.parsed, 0) << "no input was read at all: " << fuzz::report(run);
  EXPECT_GT(run.refused, 0) << "no input was refused: " << fuzz::report(run);
  std::printf("%s\n", fuzz::report(run).c_str());
}

}  // namespace

TEST(ReaderFuzz, obj_inputs_are_read_or_refused_with_a_thermodec_error) {
  const fs::path d = fuzz::work_dir("obj");
  const std::string crafted =
      "# polygons, relative indices, texture/normal slots, o/g/usemtl switches, CRLF\r\n"
      "v 0 0 0\r\nv 1 0 0 1\r\nv 1 1 0 0.5 0.5 0.5\r\nv 0 1 0\r\nvt 0 0\r\nvn 0 0 1\r\n"
      "o panel\r\nusemtl osr\r\nf 1/1/1 2/1/1 3/1/1 4/1/1\r\ng back\r\nusemtl\r\nf -1//1 -2//1 -3//1\r\n"
      "g\r\nf 1 3 4\r\n#thermodec back_material mli\r\n";
  const std::vector<std::string> corpus = {fuzz::read_bytes(kData / "satellite.obj"),
                                           fuzz::read_bytes(kSample / "satellite.obj"),
                                           written(test::unit_cube(), d, "cube.obj", false), crafted};
  expect_corpus_reads(corpus, d, "fuzz.obj", mesh_reader());
  expect_clean(fuzz::fuzz_reader(corpus, d, "fuzz.obj", kIterations, 0x0b1, mesh_reader()));
}

TEST(ReaderFuzz, ply_inputs_are_read_or_refused_with_a_thermodec_error) {
  const fs::path d = fuzz::work_dir("ply");
  const Mesh cube = test::unit_cube();
  const std::string big_endian =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nproperty float quality\n"
      "end_header\n" +
      std::string("\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00"
                  "\x3f\xf0\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00"
                  "\x00\x00\x00\x00\x00\x00\x00\x00\x3f\xf0\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00"
                  "\x03\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x02\x40\x00\x00\x00",
                  3 * 24 + 1 + 12 + 4);
  const std::string ascii_quality =
      "ply\nformat ascii 1.0\ncomment MeshLab labels\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\n"
      "property float quality\nelement edge 0\nproperty int vertex1\nend_header\n"
      "0 0 0 255\n1 0 0 0\n1 1 0 9\n0 1 0 1\n3 0 1 2 4\n4 0 2 3 1 7\n";
  const std::vector<std::string> corpus = {written(cube, d, "cube_binary.ply", true), written(cube, d, "cube_ascii.ply", false),
                                           fuzz::read_bytes(fs::path(THERMODEC_SOURCE_DIR) / "meshlab_plugin/tests/data/box.ply"),
                                           big_endian, ascii_quality};
  expect_corpus_reads(corpus, d, "fuzz.ply", mesh_reader());
  expect_clean(fuzz::fuzz_reader(corpus, d, "fuzz.ply", kIterations, 0x91e, mesh_reader()));
}

TEST(ReaderFuzz, stl_inputs_are_read_or_refused_with_a_thermodec_error) {
  const fs::path d = fuzz::work_dir("stl");
  const Mesh cube = test::unit_cube();
  // A binary STL whose 80-byte header starts with "solid" (recognised by its size).
  std::string solid_header = written(cube, d, "cube_binary.stl", true);
  solid_header.replace(0, 5, "solid");
  const std::vector<std::string> corpus = {written(cube, d, "cube_binary.stl", true),
                                           written(cube, d, "cube_ascii.stl", false), solid_header,
                                           "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                           "vertex 0 1 0\nendloop\nendfacet\nendsolid a\nsolid b\nfacet normal 0 0 0\n"
                                           "outer loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
                                           "endsolid b\n"};
  expect_corpus_reads(corpus, d, "fuzz.stl", mesh_reader());
  expect_clean(fuzz::fuzz_reader(corpus, d, "fuzz.stl", kIterations, 0x571, mesh_reader()));
}

TEST(ReaderFuzz, nastran_bdf_inputs_are_read_or_refused_with_a_thermodec_error) {
  const fs::path d = fuzz::work_dir("bdf");
  // Small-field (8 columns), large-field (GRID* with a '*' continuation), free-field (commas,
  // '+' continuation), executive control before BEGIN BULK, tabs, NASTRAN reals ("1.-3", D).
  // A fixed-field card: the name and each field padded to `width` columns (8, or 16 for large).
  auto card = [](std::initializer_list<const char*> fields, std::size_t width = 8) {
    std::string line;
    std::size_t k = 0;
    for (const char* f : fields) line += std::string(f) + std::string((k++ == 0 ? 8 : width) - std::string(f).size(), ' ');
    return line + "\n";
  };
  const std::string small_field =
      "SOL 101\nCEND\nBEGIN BULK\n$ thermodec node 1 panel\n$ thermodec material 7 osr\n"
      "$ thermodec back_material 11 mli\n" +
      card({"GRID", "1", "", "0.", "0.", "0."}) + card({"GRID", "2", "", "1.", "0.", "0."}) +
      card({"GRID", "3", "", "1.", "1.", "0."}) + card({"GRID", "4", "", "0.", "1.", "1.-3"}) +
      card({"CQUAD4", "10", "1", "1", "2", "3", "4"}) + card({"CTRIA3", "11", "1", "1", "3", "4"}) +
      card({"PSHELL", "1", "7", ".002"}) + card({"RADM", "7", "0.1", "0.8"}) + card({"CBAR", "99", "1", "1", "2"}) +
      "ENDDATA\n";
  std::string large_field;
  for (const auto& [id, x, y, z] : {std::array<const char*, 4>{"1", "0.0", "0.0", "0.0"}, {"2", "1.0", "0.0", "0.0"},
                                    {"3", "0.0", "1.0D0", "0.0"}})
    large_field += card({"GRID*", id, "", x, y}, 16) + card({"*", z}, 16);
  large_field += card({"CTRIA3", "5", "2", "1", "2", "3"}) + card({"PSHELL", "2", "3"}) + card({"RADM", "3", "0.3", "0.9"});
  const std::string free_field =
      "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\nGRID,4,,0.,0.,1.\n"
      "CTRIA3,1,4,1,3,2\nCTRIA3,2,4,1,2,4,+C1\n+C1,0.0\nCQUADR,3,,2,3,4,1\n"
      "PSHELL,4,8,0.001\nRADM,8,.5,.5\n";
  const std::string tabs = "BEGIN BULK\nGRID\t1\t\t0.\t0.\t0.\nGRID\t2\t\t1.\t0.\t0.\nGRID\t3\t\t0.\t1.\t0.\n"
                           "CTRIA3\t1\t1\t1\t2\t3\nENDDATA\n";
  const std::vector<std::string> corpus = {small_field, large_field, free_field, tabs};
  fuzz::Reader reader = [mesh = mesh_reader()](const fs::path& path, int iteration) {
    for (const BdfRadiationProperties& p : read_bdf_radiation_properties(path))
      if (!(p.absorptivity > 0.0 && p.absorptivity <= 1.0 && p.emissivity > 0.0 && p.emissivity <= 1.0))
        return std::string("RADM of ") + p.material + " out of (0, 1]";
    return mesh(path, iteration);
  };
  expect_corpus_reads(corpus, d, "fuzz.bdf", reader);
  expect_clean(fuzz::fuzz_reader(corpus, d, "fuzz.bdf", kIterations, 0xbdf, reader));
}
