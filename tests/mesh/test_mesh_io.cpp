#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "mesh/mesh_test_util.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"

using namespace thermodec;
using thermodec::test::temp_dir;
using thermodec::test::unit_cube;
using thermodec::test::write_file;

namespace {

// Expects read_mesh to throw InvalidInput whose message contains every fragment.
void expect_invalid(const std::filesystem::path& p, std::initializer_list<std::string> fragments,
                    const MeshReadOptions& options = {}) {
  try {
    read_mesh(p, options);
    ADD_FAILURE() << "no exception for " << p;
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

void expect_same_mesh(const Mesh& a, const Mesh& b, bool with_groups, bool with_materials) {
  ASSERT_EQ(a.num_faces(), b.num_faces());
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  EXPECT_EQ(a.F, b.F);
  EXPECT_EQ((a.V - b.V).cwiseAbs().maxCoeff(), 0.0);
  if (with_groups) {
    EXPECT_EQ(a.node_names, b.node_names);
    EXPECT_EQ(a.face_node, b.face_node);
  }
  if (with_materials) {
    EXPECT_EQ(a.material_names, b.material_names);
    EXPECT_EQ(a.face_material, b.face_material);
    EXPECT_EQ(a.face_back_material, b.face_back_material);
  }
}

std::string le_u32(std::uint32_t v) { std::string s(4, '\0'); std::memcpy(s.data(), &v, 4); return s; }
std::string le_f32(float v) { std::string s(4, '\0'); std::memcpy(s.data(), &v, 4); return s; }

std::string binary_stl(const std::vector<std::array<float, 9>>& tris, std::uint32_t announced) {
  std::string s(80, ' ');
  s += le_u32(announced);
  for (const auto& t : tris) {
    s += le_f32(0) + le_f32(0) + le_f32(0);
    for (float x : t) s += le_f32(x);
    s += std::string(2, '\0');
  }
  return s;
}

}  // namespace

TEST(MeshIO, obj_round_trip_keeps_groups_materials_and_back_sides) {
  auto d = temp_dir("obj_rt");
  const Mesh cube = unit_cube();
  write_mesh(d / "cube.obj", cube);
  expect_same_mesh(read_mesh(d / "cube.obj"), cube, true, true);
}

TEST(MeshIO, ply_binary_and_ascii_round_trips_keep_groups_and_materials) {
  auto d = temp_dir("ply_rt");
  const Mesh cube = unit_cube();
  write_mesh(d / "bin.ply", cube);
  MeshWriteOptions ascii;
  ascii.binary = false;
  write_mesh(d / "ascii.ply", cube, ascii);
  expect_same_mesh(read_mesh(d / "bin.ply"), cube, true, true);
  expect_same_mesh(read_mesh(d / "ascii.ply"), cube, true, true);
}

TEST(MeshIO, stl_binary_round_trip_keeps_geometry_and_welds_corners) {
  auto d = temp_dir("stl_rt");
  const Mesh cube = unit_cube();
  write_mesh(d / "cube.stl", cube);
  const Mesh back = read_mesh(d / "cube.stl");
  // 36 stored corners weld back to the 8 cube vertices, in first-use order.
  EXPECT_EQ(back.num_vertices(), 8);
  ASSERT_EQ(back.num_faces(), 12);
  for (int f = 0; f < 12; ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back.V.row(back.F(f, k)), cube.V.row(cube.F(f, k)));
  EXPECT_TRUE(back.node_names.empty());
  EXPECT_EQ(back.face_node, Eigen::VectorXi::Constant(12, -1));
}

TEST(MeshIO, stl_ascii_round_trip_keeps_nodes_as_solids) {
  auto d = temp_dir("stl_ascii_rt");
  const Mesh cube = unit_cube();
  MeshWriteOptions ascii;
  ascii.binary = false;
  write_mesh(d / "cube.stl", cube, ascii);
  const Mesh back = read_mesh(d / "cube.stl");
  EXPECT_EQ(back.num_vertices(), 8);
  EXPECT_EQ(back.node_names, cube.node_names);
  EXPECT_EQ(back.face_node, cube.face_node);
}

TEST(MeshIO, obj_polygons_are_fan_triangulated_and_relative_indices_resolved) {
  auto d = temp_dir("obj_poly");
  auto p = write_file(d / "quad.obj",
                      "# a unit square as one quad, then a triangle with relative indices\n"
                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 0.5 0.5 0.5\n"
                      "o panel\nusemtl cells\nf 1/1/1 2/2/1 3//1 4\n"
                      "g other\nusemtl\nv 0 0 1\nf -5 -4 -1\n");
  const Mesh m = read_mesh(p);
  ASSERT_EQ(m.num_faces(), 3);
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(m.F.row(2), Eigen::RowVector3i(0, 1, 4));
  EXPECT_EQ(m.node_names, (std::vector<std::string>{"panel", "other"}));
  EXPECT_EQ(m.face_node, Eigen::Vector3i(0, 0, 1));
  EXPECT_EQ(m.material_names, (std::vector<std::string>{"cells"}));
  EXPECT_EQ(m.face_material, Eigen::Vector3i(0, 0, -1));
}

TEST(MeshIO, obj_without_groups_has_unassigned_faces) {
  auto d = temp_dir("obj_nogroup");
  const Mesh m = read_mesh(write_file(d / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_TRUE(m.node_names.empty());
  EXPECT_EQ(m.face_node[0], -1);
  EXPECT_EQ(m.face_material[0], -1);
  EXPECT_EQ(m.face_back_material[0], -1);
}

TEST(MeshIO, ply_quality_is_read_as_node_when_there_is_no_node_property) {
  auto d = temp_dir("ply_quality");
  auto p = write_file(d / "q.ply",
                      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                      "property float quality\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 1\n3 0 2 3 0\n");
  const Mesh m = read_mesh(p);
  EXPECT_EQ(m.face_node, Eigen::Vector2i(1, 0));
  EXPECT_EQ(m.node_names, (std::vector<std::string>{"node_0", "node_1"}));
}

TEST(MeshIO, ply_non_integer_quality_is_ignored) {
  auto d = temp_dir("ply_quality2");
  auto p = write_file(d / "q.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                      "property float quality\nend_header\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2 0.37\n");
  const Mesh m = read_mesh(p);
  EXPECT_EQ(m.face_node[0], -1);
  EXPECT_TRUE(m.node_names.empty());
}

TEST(MeshIO, ply_big_endian_with_extra_properties_and_elements_is_read) {
  auto d = temp_dir("ply_be");
  std::string s =
      "ply\nformat binary_big_endian 1.0\ncomment thermodec node 0 solar wing\n"
      "element vertex 3\nproperty float x\nproperty uchar red\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uint short vertex_indices\nproperty short node\n"
      "element edge 1\nproperty int a\nproperty int b\nend_header\n";
  auto be = [](const void* p, std::size_t n) { std::string b(static_cast<const char*>(p), n); std::reverse(b.begin(), b.end()); return b; };
  const float pts[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  for (auto& v : pts) {
    s += be(&v[0], 4) + std::string(1, '\x07') + be(&v[1], 4) + be(&v[2], 4);
  }
  const std::uint32_t three = 3;
  s += be(&three, 4);
  for (std::int16_t i : {0, 1, 2}) s += be(&i, 2);
  const std::int16_t node = 0;
  s += be(&node, 2);
  s += std::string(8, '\0');  // the edge
  const Mesh m = read_mesh(write_file(d / "be.ply", s));
  ASSERT_EQ(m.num_faces(), 1);
  EXPECT_EQ(m.V(1, 0), 2.0);
  EXPECT_EQ(m.V(2, 1), 2.0);
  EXPECT_EQ(m.node_names, (std::vector<std::string>{"solar wing"}));
  EXPECT_EQ(m.face_node[0], 0);
}

TEST(MeshIO, nasa_style_binary_stl_header_starting_with_solid_is_read_as_binary) {
  auto d = temp_dir("stl_solid_header");
  std::string s = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}}, 1);
  s.replace(0, 5, "solid");
  const Mesh m = read_mesh(write_file(d / "t.stl", s));
  EXPECT_EQ(m.num_faces(), 1);
  EXPECT_EQ(m.num_vertices(), 3);
}

// ---- malformed input: every case names the file and the line or face ----

TEST(MeshIOErrors, empty_files_are_rejected_in_every_format) {
  auto d = temp_dir("empty");
  for (const char* name : {"e.obj", "e.ply", "e.stl"}) expect_invalid(write_file(d / name, ""), {name, "empty"});
  expect_invalid(write_file(d / "c.obj", "# only a comment\n"), {"c.obj", "empty mesh"});
  expect_invalid(write_file(d / "v.obj", "v 0 0 0\nv 1 0 0\n"), {"v.obj", "no faces"});
  expect_invalid(write_file(d / "z.stl", binary_stl({}, 0)), {"z.stl", "0 triangles"});
}

TEST(MeshIOErrors, non_finite_coordinates_name_the_line) {
  auto d = temp_dir("nan");
  expect_invalid(write_file(d / "n.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), {"n.obj:2:", "non-finite"});
  expect_invalid(write_file(d / "i.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"), {"i.obj:3:", "non-finite"});
  expect_invalid(write_file(d / "big.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n"), {"big.obj:2:", "non-finite"});
  expect_invalid(write_file(d / "x.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n"), {"x.obj:2:", "zero"});
  expect_invalid(write_file(d / "n.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex NaN 0 0\n"
                                         "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n"),
                 {"n.stl:5:", "non-finite"});
  expect_invalid(write_file(d / "n.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                         "end_header\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n"),
                 {"n.ply:12:", "vertex 2", "non-finite"});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  expect_invalid(write_file(d / "b.stl", binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, nan, 0, 0, 0, 1, 0}}, 2)),
                 {"b.stl", "face 1", "non-finite"});
}

TEST(MeshIOErrors, out_of_range_zero_and_negative_indices_name_line_or_face) {
  auto d = temp_dir("index");
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_invalid(write_file(d / "a.obj", v + "f 1 2 4\n"), {"a.obj:4:", "vertex index 4 out of range", "3 vertices"});
  expect_invalid(write_file(d / "b.obj", v + "f 0 1 2\n"), {"b.obj:4:", "index 0"});
  expect_invalid(write_file(d / "c.obj", v + "f -1 -2 -4\n"), {"c.obj:4:", "relative vertex index -4"});
  expect_invalid(write_file(d / "d.obj", v + "f 1 2\n"), {"d.obj:4:", "at least 3"});
  expect_invalid(write_file(d / "e.obj", v + "f 1 2 x\n"), {"e.obj:4:", "'x'"});
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_invalid(write_file(d / "a.ply", ply + "3 0 1 3\n"), {"a.ply:14:", "face 1", "vertex index 3 out of range"});
  expect_invalid(write_file(d / "b.ply", ply + "3 0 -1 2\n"), {"b.ply:14:", "face 1", "negative vertex index"});
  // Binary PLY errors name the face.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 9; ++i) bin += le_f32(i == 3 || i == 7 ? 1.f : 0.f);
  bin += std::string(1, '\3') + le_u32(0) + le_u32(1) + le_u32(7);
  expect_invalid(write_file(d / "c.ply", bin), {"c.ply: face 0", "vertex index 7 out of range"});
}

TEST(MeshIOErrors, truncated_binary_files_name_the_face) {
  auto d = temp_dir("trunc");
  std::string stl = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, 0, 1, 0}}, 3);
  expect_invalid(write_file(d / "t.stl", stl), {"t.stl", "truncated", "3 triangles", "face 2"});
  expect_invalid(write_file(d / "h.stl", std::string(50, '\1')), {"h.stl", "truncated", "84"});
  const Mesh cube = unit_cube();
  write_mesh(d / "cube.ply", cube);
  std::ifstream in(d / "cube.ply", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  expect_invalid(write_file(d / "t.ply", bytes.substr(0, bytes.size() - 10)), {"t.ply", "truncated", "face 11"});
  expect_invalid(write_file(d / "h.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"), {"h.ply", "end_header"});
  expect_invalid(write_file(d / "a.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                         "property float z\nend_header\n0 0 0\n1 0 0\n"),
                 {"a.ply", "truncated", "vertex 2"});
  expect_invalid(write_file(d / "t.obj.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"), {"truncated"});
}

TEST(MeshIOErrors, malformed_ply_headers_name_the_line) {
  auto d = temp_dir("plyhdr");
  expect_invalid(write_file(d / "a.ply", "plx\n"), {"a.ply:1:", "not a PLY"});
  expect_invalid(write_file(d / "b.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"),
                 {"b.ply:4:", "quad"});
  expect_invalid(write_file(d / "c.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                         "property float z\nend_header\n0 0 0 9\n1 0 0\n0 1 0\n"),
                 {"c.ply:8:", "vertex 0"});
}

TEST(MeshIOErrors, unknown_extension_and_missing_file_are_reported) {
  auto d = temp_dir("ext");
  expect_invalid(write_file(d / "a.off", "OFF\n"), {"a.off", "unknown mesh format"});
  EXPECT_THROW(read_mesh(d / "missing.obj"), IOError);
  EXPECT_THROW(write_mesh(d / "x.dae", unit_cube()), InvalidInput);
}

TEST(MeshIO, degenerate_faces_are_reported_and_dropped_or_kept) {
  auto d = temp_dir("degenerate");
  auto p = write_file(d / "deg.obj",
                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                      "f 1 2 3\nf 1 2 4\nf 1 1 3\n");  // collinear, then repeated corner
  MeshReadReport report;
  const Mesh dropped = read_mesh(p, {}, report);
  EXPECT_EQ(dropped.num_faces(), 1);
  EXPECT_EQ(report.degenerate_faces, (std::vector<int>{1, 2}));
  EXPECT_TRUE(report.degenerate_faces_dropped);
  MeshReadOptions keep;
  keep.drop_degenerate_faces = false;
  const Mesh kept = read_mesh(p, keep, report);
  EXPECT_EQ(kept.num_faces(), 3);
  EXPECT_FALSE(report.degenerate_faces_dropped);
  expect_invalid(write_file(d / "all.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), {"all.obj", "degenerate"});
}

TEST(MeshIO, obj_duplicate_vertices_are_welded_within_tolerance_only) {
  auto d = temp_dir("objweld");
  auto p = write_file(d / "w.obj",
                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e-12 0 0\nv 1 1e-6 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\n");
  EXPECT_EQ(read_mesh(p).num_vertices(), 4);  // default 1e-9: the 1e-6 offset stays apart
  MeshReadOptions loose;
  loose.weld_tolerance = 1e-5;
  EXPECT_EQ(read_mesh(p, loose).num_vertices(), 3);
  MeshReadOptions off;
  off.weld_tolerance = -1;
  EXPECT_EQ(read_mesh(p, off).num_vertices(), 6);
}

TEST(MeshIO, write_refuses_to_overwrite_protected_input) {
  auto d = temp_dir("protect");
  write_mesh(d / "in.obj", unit_cube());
  MeshWriteOptions o;
  o.protected_inputs = {d / "in.obj"};
  EXPECT_THROW(write_mesh(d / "in.obj", unit_cube(), o), InvalidInput);
}

TEST(MeshIO, write_rejects_inconsistent_meshes) {
  Mesh m = unit_cube();
  m.F(3, 1) = 8;
  auto d = temp_dir("badwrite");
  EXPECT_THROW(write_mesh(d / "x.obj", m), InvalidInput);
  m = unit_cube();
  m.face_node[0] = 6;
  EXPECT_THROW(write_mesh(d / "x.ply", m), InvalidInput);
  EXPECT_FALSE(std::filesystem::exists(d / "x.ply"));
}

TEST(SharedModelsMeshIO, nasa_binary_stls_read_with_their_documented_triangle_counts) {
  const std::filesystem::path dir = std::filesystem::path(THERMODEC_SHARED_DIR) / "models" / "nasa";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " missing";
  const std::pair<const char*, int> files[] = {{"tdrs.stl", 20026}, {"NPP_16.stl", 4036}, {"Juno.stl", 17136}};
  for (const auto& [name, triangles] : files) {
    MeshReadOptions keep;
    keep.drop_degenerate_faces = false;
    const Mesh m = read_mesh(dir / name, keep);
    EXPECT_EQ(m.num_faces(), triangles) << name;
    EXPECT_LT(m.num_vertices(), m.num_faces()) << name << ": corners were not welded";
  }
}

TEST(MeshIOErrors, every_truncation_and_byte_corruption_reads_or_throws_a_thermodec_error) {
  // Robustness sweep over small files: no crash, no foreign exception, whatever the damage.
  auto d = temp_dir("fuzz");
  const Mesh cube = unit_cube();
  MeshWriteOptions ascii;
  ascii.binary = false;
  write_mesh(d / "c.obj", cube);
  write_mesh(d / "c.ply", cube);
  write_mesh(d / "a.ply", cube, ascii);
  write_mesh(d / "c.stl", cube);
  write_mesh(d / "a.stl", cube, ascii);
  int reads = 0, errors = 0;
  for (const char* name : {"c.obj", "c.ply", "a.ply", "c.stl", "a.stl"}) {
    std::ifstream in(d / name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string ext = std::filesystem::path(name).extension().string();
    auto attempt = [&](const std::string& data) {
      // A fresh name per attempt: rewriting one file would make ext4 flush it every time.
      const auto p = write_file(d / ("damaged" + std::to_string(reads + errors) + ext), data);
      try {
        read_mesh(p);
        ++reads;
      } catch (const InvalidInput&) {
        ++errors;
      }
      std::filesystem::remove(p);
    };
    for (std::size_t n = 0; n < bytes.size(); n += 3) attempt(bytes.substr(0, n));
    for (std::size_t i = 0; i < bytes.size(); i += 2)
      for (char c : {'\0', '\xff', '9', '-', '\n'}) {
        std::string damaged = bytes;
        damaged[i] = c;
        attempt(damaged);
      }
  }
  EXPECT_GT(reads, 0);
  EXPECT_GT(errors, 0);
}
