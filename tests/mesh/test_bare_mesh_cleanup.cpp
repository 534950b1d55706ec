// cleanup_bare_mesh on tiny hand-built meshes: each defect alone, with the exact count expected.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "mesh_test_util.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/bare_mesh_cleanup.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/mesh/io.h"

using namespace thermodec;

namespace {

// A bare copy of the unit cube (no groups, no materials, one-sided), shifted by `offset`.
Mesh bare_cube(const Eigen::RowVector3d& offset = Eigen::RowVector3d::Zero()) {
  Mesh m = test::unit_cube();
  m.V.rowwise() += offset;
  const int nf = m.num_faces();
  m.face_node = Eigen::VectorXi::Constant(nf, -1);
  m.face_material = Eigen::VectorXi::Constant(nf, -1);
  m.face_back_material = Eigen::VectorXi::Constant(nf, -1);
  m.node_names.clear();
  m.material_names.clear();
  return m;
}

// Appends b to a (vertices re-indexed, attributes concatenated).
Mesh join(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  auto cat = [](const Eigen::VectorXi& x, const Eigen::VectorXi& y) {
    Eigen::VectorXi z(x.size() + y.size());
    z << x, y;
    return z;
  };
  m.face_node = cat(a.face_node, b.face_node);
  m.face_material = cat(a.face_material, b.face_material);
  m.face_back_material = cat(a.face_back_material, b.face_back_material);
  return m;
}

// A unit square sheet at height z (two triangles facing +z), away from the cube.
Mesh bare_sheet(double z) {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 3, 0, z, 4, 0, z, 4, 1, z, 3, 1, z;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  m.face_node = m.face_material = m.face_back_material = Eigen::VectorXi::Constant(2, -1);
  return m;
}

int count_two_sided(const BareMeshCleanupResult& r) { return r.two_sided.sum(); }

}  // namespace

TEST(BareMeshCleanup, closed_cube_is_left_one_sided_and_unchanged) {
  const BareMeshCleanupResult r = cleanup_bare_mesh(bare_cube());
  EXPECT_EQ(r.mesh.num_faces(), 12);
  EXPECT_EQ(r.report.closed_components, 1);
  EXPECT_EQ(r.report.open_components, 0);
  EXPECT_EQ(count_two_sided(r), 0);
  EXPECT_FALSE(r.report.changed());
}

TEST(BareMeshCleanup, inside_out_cube_is_turned_outward) {
  Mesh m = bare_cube();
  m.F.col(1).swap(m.F.col(2));
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);
  EXPECT_EQ(r.report.faces_flipped, 12);
  const Eigen::MatrixXd n = face_normals(r.mesh.V, r.mesh.F);
  EXPECT_GT(n(0, 0), 0.99);  // the +x side points to +x again
}

TEST(BareMeshCleanup, duplicated_face_is_dropped_once) {
  Mesh m = bare_cube();
  Mesh d = m;
  d.F.conservativeResize(13, 3);
  d.F.row(12) = m.F.row(4);
  for (Eigen::VectorXi* a : {&d.face_node, &d.face_material, &d.face_back_material}) {
    a->conservativeResize(13);
    (*a)[12] = -1;
  }
  const BareMeshCleanupResult r = cleanup_bare_mesh(d);
  EXPECT_EQ(r.report.duplicate_faces_dropped, 1);
  EXPECT_EQ(r.report.back_to_back_pairs_merged, 0);
  EXPECT_EQ(r.mesh.num_faces(), 12);
  EXPECT_EQ(r.report.closed_components, 1);
  EXPECT_EQ(count_two_sided(r), 0);
}

TEST(BareMeshCleanup, back_to_back_faces_become_one_two_sided_face) {
  Mesh s = bare_sheet(0.5);
  Mesh m = join(s, s);
  m.F.row(2) << 4, 6, 5;  // reversed copies of the two triangles
  m.F.row(3) << 4, 7, 6;
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);  // the weld joins the copies' vertices
  EXPECT_EQ(r.report.back_to_back_pairs_merged, 2);
  EXPECT_EQ(r.report.duplicate_faces_dropped, 0);
  ASSERT_EQ(r.mesh.num_faces(), 2);
  EXPECT_EQ(count_two_sided(r), 2);
}

TEST(BareMeshCleanup, open_sheet_becomes_two_sided_and_the_closed_part_does_not) {
  Mesh m = join(bare_cube(), bare_sheet(0.5));
  m.face_material.setZero();  // with a known front material the back gets it too
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);
  EXPECT_EQ(r.report.open_components, 1);
  EXPECT_EQ(r.report.closed_components, 1);
  EXPECT_EQ(r.report.open_sheet_faces_made_two_sided, 2);
  ASSERT_EQ(r.mesh.num_faces(), 14);
  for (int f = 0; f < 14; ++f) {
    const bool sheet = r.source_face[f] >= 12;
    EXPECT_EQ(r.two_sided[f], sheet ? 1 : 0) << "face " << f;
    EXPECT_EQ(r.mesh.face_back_material[f], sheet ? 0 : -1) << "face " << f;
  }
}

TEST(BareMeshCleanup, touching_faces_of_two_cubes_are_dropped) {
  // Cube B sits on cube A: A's top (z = 1, facing +z) and B's bottom (z = 1, facing -z) touch.
  const Mesh m = join(bare_cube(), bare_cube(Eigen::RowVector3d(0, 0, 1)));
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);  // welded: the touching faces are a reversed pair
  EXPECT_EQ(r.report.back_to_back_pairs_merged, 0);
  EXPECT_EQ(r.report.closed_components, 1);  // one 1 x 1 x 2 box remains
  EXPECT_EQ(r.report.coincident_faces_dropped, 4);
  EXPECT_NEAR(r.report.coincident_area_dropped_m2, 2.0, 1e-12);
  ASSERT_EQ(r.mesh.num_faces(), 20);
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
    const int s = r.source_face[f] % 12;
    EXPECT_TRUE(!(r.source_face[f] < 12 && s / 2 == 4) && !(r.source_face[f] >= 12 && s / 2 == 5)) << "face " << f;
  }
}

TEST(BareMeshCleanup, touching_faces_with_separate_vertices_are_dropped) {
  // B floats 1e-6 m above A: beyond the weld tolerance (1e-7 x diagonal), within the contact
  // distance (1e-5 x diagonal), so the touching faces share no vertex and step 4 finds them.
  const Mesh m = join(bare_cube(), bare_cube(Eigen::RowVector3d(0, 0, 1 + 1e-6)));
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);
  EXPECT_EQ(r.report.vertices_welded, 0);
  EXPECT_EQ(r.report.closed_components, 2);
  EXPECT_EQ(r.report.coincident_faces_dropped, 4);
  EXPECT_EQ(r.mesh.num_faces(), 20);
}

TEST(BareMeshCleanup, faces_a_gap_apart_are_kept) {
  // 1 % of the size apart is a real gap (the tolerance is 1e-5 of the diagonal).
  const Mesh m = join(bare_cube(), bare_cube(Eigen::RowVector3d(0, 0, 1.01)));
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);
  EXPECT_EQ(r.report.coincident_faces_dropped, 0);
  EXPECT_EQ(r.mesh.num_faces(), 24);
}

TEST(BareMeshCleanup, closed_part_with_a_sheet_inside_radiates_from_both_sides) {
  // A 3 m cube around the sheet (x 3..4, y 0..1, z 0.5): the cube is a hollow structure.
  Mesh big = bare_cube();
  big.V = (big.V * 3.0).rowwise() + Eigen::RowVector3d(2, -1, -1);
  Mesh m = join(big, bare_sheet(0.5));
  m.face_material.setZero();
  const BareMeshCleanupResult r = cleanup_bare_mesh(m);
  EXPECT_EQ(r.report.enclosing_shells, 1);
  EXPECT_EQ(r.report.enclosed_faces, 2);
  EXPECT_EQ(r.report.shell_faces_made_two_sided, 12);
  EXPECT_EQ(r.report.open_sheet_faces_made_two_sided, 2);
  ASSERT_EQ(r.mesh.num_faces(), 14);
  EXPECT_EQ(count_two_sided(r), 14);
  for (int f = 0; f < 14; ++f) EXPECT_EQ(r.mesh.face_back_material[f], 0) << "face " << f;
  EXPECT_TRUE(r.report.changed());
  EXPECT_NE(r.report.summary().find("closed parts with faces inside, made two-sided: 1 (12 faces; 2 faces inside)"),
            std::string::npos)
      << r.report.summary();
}

TEST(BareMeshCleanup, only_the_outer_of_nested_closed_parts_becomes_two_sided) {
  Mesh big = bare_cube();
  big.V = (big.V * 3.0).rowwise() - Eigen::RowVector3d(1, 1, 1);
  const BareMeshCleanupResult r = cleanup_bare_mesh(join(bare_cube(), big));
  EXPECT_EQ(r.report.enclosing_shells, 1);
  EXPECT_EQ(r.report.enclosed_faces, 12);
  ASSERT_EQ(r.mesh.num_faces(), 24);
  for (int f = 0; f < 24; ++f) EXPECT_EQ(r.two_sided[f], r.source_face[f] >= 12 ? 1 : 0) << "face " << f;
  BareMeshCleanupOptions off;
  off.two_sided_enclosing_shells = false;
  EXPECT_EQ(count_two_sided(cleanup_bare_mesh(join(bare_cube(), big), off)), 0);
}

TEST(BareMeshCleanup, a_part_touching_or_beside_a_closed_part_is_not_inside_it) {
  // Side by side (sharing the x = 1 plane, vertices 1e-6 apart: step 4 drops the contact) and
  // one cube beside another: nothing is inside.
  for (const Eigen::RowVector3d offset : {Eigen::RowVector3d(1 + 1e-6, 0, 0), Eigen::RowVector3d(1.5, 0.5, 0.5)}) {
    const BareMeshCleanupResult r = cleanup_bare_mesh(join(bare_cube(), bare_cube(offset)));
    EXPECT_EQ(r.report.enclosing_shells, 0) << offset;
    EXPECT_EQ(r.report.enclosed_faces, 0) << offset;
  }
}

TEST(BareMeshCleanup, a_sheet_lying_on_a_larger_sheet_is_dropped_and_one_a_gap_away_is_kept) {
  // A 3 x 3 sheet (x 2..5, y -1..2) in the plane of the unit sheet (x 3..4, y 0..1), facing
  // the other way: one surface where they overlap, the larger layer stays.
  Mesh big = bare_sheet(0.5);
  big.V << 2, -1, 0.5, 2, 2, 0.5, 5, 2, 0.5, 5, -1, 0.5;  // corners in reverse order: facing -z
  for (const double dz : {0.0, 0.01}) {
    const BareMeshCleanupResult r = cleanup_bare_mesh(join(bare_sheet(0.5 + dz), big));
    EXPECT_EQ(r.report.overlapping_sheet_faces_dropped, dz == 0.0 ? 2 : 0) << dz;
    ASSERT_EQ(r.mesh.num_faces(), dz == 0.0 ? 2 : 4) << dz;
    EXPECT_EQ(r.source_face[0], dz == 0.0 ? 2 : 0) << dz;
  }
}

TEST(BareMeshCleanup, same_mesh_gives_same_result) {
  const Mesh m = join(join(bare_cube(), bare_cube(Eigen::RowVector3d(0, 0, 1))), bare_sheet(0.5));
  const BareMeshCleanupResult a = cleanup_bare_mesh(m), b = cleanup_bare_mesh(m);
  EXPECT_EQ(a.mesh.F, b.mesh.F);
  EXPECT_EQ(a.mesh.V, b.mesh.V);
  EXPECT_EQ(a.two_sided, b.two_sided);
}

TEST(BareMeshCleanup, nan_coordinate_is_refused) {
  Mesh m = bare_cube();
  m.V(3, 1) = std::nan("");
  EXPECT_THROW(cleanup_bare_mesh(m), InvalidInput);
}

TEST(SharedModelsBareMeshCleanup, nasa_meshes_are_cleaned_quickly_with_their_open_sheets_two_sided) {
  const std::filesystem::path dir = std::filesystem::path(THERMODEC_SHARED_DIR) / "models" / "nasa";
  if (!std::filesystem::exists(dir / "NPP_16.stl")) GTEST_SKIP() << "no " << dir;
  for (const char* name : {"NPP_16.stl", "Juno.stl", "tdrs.stl"}) {
    const Mesh raw = read_mesh(dir / name);
    const auto t0 = std::chrono::steady_clock::now();
    const BareMeshCleanupResult r = cleanup_bare_mesh(raw);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s: %s(%.2f s)\n", name, r.report.summary().c_str(), seconds);
    EXPECT_LT(seconds, 10.0) << name;
    EXPECT_GT(r.report.open_components, 0) << name;
    EXPECT_EQ(count_two_sided(r) > 0, true) << name;
    EXPECT_LE(r.mesh.num_faces(), raw.num_faces() + r.report.t_junctions_split) << name;
    if (std::string(name) == "NPP_16.stl") {  // the counts docs/benchmarks.md quotes
      EXPECT_EQ(r.report.faces_out, 3965);
      EXPECT_EQ(r.report.closed_components, 19);
      EXPECT_EQ(r.report.open_components, 48);
      EXPECT_EQ(r.report.open_sheet_faces_made_two_sided, 2967);
    }
  }
}
