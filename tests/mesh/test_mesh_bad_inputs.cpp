// Malformed meshes that used to crash, hang or be accepted silently: each is refused with a
// message naming the file and what is wrong, in bounded time and memory.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <string>

#include "mesh_test_util.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"

using namespace thermodec;
using thermodec::test::temp_dir;
using thermodec::test::write_file;

namespace {

template <class E>
void expect_error(const std::filesystem::path& p, std::initializer_list<std::string> fragments) {
  try {
    read_mesh(p);
    ADD_FAILURE() << "no exception for " << p;
  } catch (const E& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

const char* kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

}  // namespace

TEST(MeshBadInputs, ply_declaring_the_vertex_element_twice_is_refused) {
  auto d = temp_dir("ply_twice");
  const auto p = write_file(d / "t.ply",
                            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\n"
                            "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 0 0\n");
  expect_error<InvalidInput>(p, {"t.ply", "'vertex' declared twice"});
}

TEST(MeshBadInputs, ply_element_without_properties_is_refused_not_looped_over) {
  auto d = temp_dir("ply_noprop");
  const auto p = write_file(d / "t.ply",
                            "ply\nformat binary_little_endian 1.0\nelement junk 9000000000000000000\n"
                            "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
  const auto start = std::chrono::steady_clock::now();
  expect_error<InvalidInput>(p, {"t.ply", "junk", "no properties"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

TEST(MeshBadInputs, ply_count_larger_than_the_file_is_refused_before_reading) {
  auto d = temp_dir("ply_huge");
  const auto p = write_file(d / "t.ply",
                            "ply\nformat binary_little_endian 1.0\nelement junk 9000000000000000000\nproperty uchar a\n"
                            "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
  expect_error<InvalidInput>(p, {"t.ply", "junk", "truncated", "more than the"});
}

TEST(MeshBadInputs, obj_garbage_after_an_index_is_refused) {
  auto d = temp_dir("obj_garbage");
  expect_error<InvalidInput>(write_file(d / "t.obj", std::string(kTriangle) + "f 1/a 2 3\n"), {"t.obj:4", "1/a"});
  // The usual corner forms still read.
  EXPECT_EQ(read_mesh(write_file(d / "ok.obj", std::string(kTriangle) + "f 1/1 2//2 3/3/3\n")).num_faces(), 1);
}

TEST(MeshBadInputs, obj_face_using_a_vertex_defined_later_is_refused) {
  auto d = temp_dir("obj_later");
  expect_error<InvalidInput>(write_file(d / "t.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n"),
                             {"t.obj:3", "defined above this face"});
}

TEST(MeshBadInputs, obj_most_negative_index_is_refused_without_overflow) {
  auto d = temp_dir("obj_min");
  expect_error<InvalidInput>(write_file(d / "t.obj", std::string(kTriangle) + "f -9223372036854775808 2 3\n"),
                             {"t.obj:4", "points before the first vertex"});
}

TEST(MeshBadInputs, obj_nul_byte_is_refused) {
  auto d = temp_dir("obj_nul");
  expect_error<InvalidInput>(write_file(d / "t.obj", std::string(kTriangle) + "usemtl a" + std::string(1, '\0') + "b\nf 1 2 3\n"),
                             {"t.obj:4", "NUL"});
}

TEST(MeshBadInputs, device_and_folder_paths_are_refused_before_reading) {
  auto d = temp_dir("device");
  std::filesystem::create_symlink("/dev/zero", d / "zero.stl");
  expect_error<IOError>(d / "zero.stl", {"zero.stl", "not a regular file"});
  ASSERT_EQ(::mkfifo((d / "fifo.obj").c_str(), 0600), 0);
  expect_error<IOError>(d / "fifo.obj", {"fifo.obj", "not a regular file"});
}

// 10 000 triangles on one edge (a "book"): pairwise links would be 10^8 entries (gigabytes);
// the hub edge keeps automatic nodes linear in memory and fast.
TEST(MeshBadInputs, automatic_nodes_on_a_ten_thousand_page_book_stay_fast) {
  const int pages = 10000;
  Mesh m;
  m.V.resize(pages + 2, 3);
  m.V.row(0) << 0, 0, 0;
  m.V.row(1) << 0, 0, 1;
  m.F.resize(pages, 3);
  for (int i = 0; i < pages; ++i) {
    const double a = 2.0 * 3.14159265358979 * i / pages;
    m.V.row(i + 2) << std::cos(a), std::sin(a), 0.5;
    m.F.row(i) << 0, 1, i + 2;
  }
  const auto start = std::chrono::steady_clock::now();
  assign_automatic_nodes(m);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
  EXPECT_EQ(m.face_node.size(), pages);
  EXPECT_GE(m.face_node.minCoeff(), 0);
}

TEST(MeshBadInputs, coordinates_whose_areas_overflow_are_refused_by_every_reader) {
  auto d = temp_dir("overflow");
  expect_error<InvalidInput>(write_file(d / "far.obj", "v 1e308 0 0\nv -1e308 0 0\nv 0 1e308 0\nf 1 2 3\n"),
                             {"far.obj", "vertex 0", "beyond"});
  expect_error<InvalidInput>(
      write_file(d / "far.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                                "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                "0 0 0\n1e200 0 0\n0 1e200 0\n3 0 1 2\n"),
      {"far.ply", "vertex 1"});
  expect_error<InvalidInput>(write_file(d / "far.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                                       "vertex 2e12 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n"),
                             {"far.stl", "vertex"});
  expect_error<InvalidInput>(write_file(d / "far.bdf", "GRID,1,,0.,0.,0.\nGRID,2,,1.+308,0.,0.\nGRID,3,,0.,1.,0.\n"
                                                       "CTRIA3,1,1,1,2,3\nENDDATA\n"),
                             {"far.bdf", "vertex 1"});
  // 1e12 itself is accepted: areas of 1e24 are finite.
  EXPECT_NO_THROW(read_mesh(write_file(d / "edge.obj", "v 0 0 0\nv 1e12 0 0\nv 0 1e12 0\nf 1 2 3\n")));
}

TEST(MeshBadInputs, names_with_control_characters_are_refused_without_echoing_them) {
  auto d = temp_dir("names");
  try {
    read_mesh(write_file(d / "esc.obj", std::string("g a\x1b]0;t\x07\xe2\x80\xae") + "\n" + kTriangle + "f 1 2 3\n"));
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("control characters"), std::string::npos) << msg;
    EXPECT_NE(msg.find("\\x1b"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\x1b'), std::string::npos);
    EXPECT_EQ(msg.find("\xe2\x80\xae"), std::string::npos);
  }
  expect_error<InvalidInput>(write_file(d / "esc.bdf", "$ thermodec node 1 a\x01" "b\nGRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\n"
                                                       "GRID,3,,0.,1.,0.\nCTRIA3,1,1,1,2,3\nENDDATA\n"),
                             {"esc.bdf", "node name", "\\x01"});
}

TEST(MeshBadInputs, nastran_duplicate_elements_and_non_positive_ids_are_refused) {
  auto d = temp_dir("bdf_ids");
  const std::string grids = "GRID,1,,0.,0.,0.\nGRID,2,,1.,0.,0.\nGRID,3,,0.,1.,0.\nGRID,4,,1.,1.,0.\n";
  expect_error<InvalidInput>(write_file(d / "dup.bdf", grids + "CTRIA3,7,1,1,2,3\nCQUAD4,7,1,1,2,4,3\nENDDATA\n"),
                             {"dup.bdf:6", "element 7 is defined twice"});
  expect_error<InvalidInput>(write_file(d / "neg.bdf", "GRID,-2,,0.,0.,0.\n" + grids + "CTRIA3,1,1,1,2,3\nENDDATA\n"),
                             {"neg.bdf:1", "ID", "positive"});
  expect_error<InvalidInput>(write_file(d / "zero.bdf", grids + "CTRIA3,0,1,1,2,3\nENDDATA\n"), {"EID", "positive"});
  // A field of a megabyte is quoted short.
  try {
    read_mesh(write_file(d / "huge.bdf", "GRID,1,," + std::string(1 << 20, '7') + "x,0.,0.\n" + grids + "ENDDATA\n"));
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_LT(std::string(e.what()).size(), 300u) << e.what();
    EXPECT_NE(std::string(e.what()).find("(1048577 bytes)"), std::string::npos) << e.what();
  }
}
