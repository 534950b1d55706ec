#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;

namespace {

// Axis-aligned box [0,sx]x[0,sy]x[0,sz], every side an n x n grid of triangle pairs with
// shared (welded) vertices, normals pointing outwards.
Mesh from_lists(const std::vector<Eigen::Vector3d>& verts, const std::vector<Eigen::Vector3i>& faces);

Mesh grid_box(int n, double sx = 1.0, double sy = 1.0, double sz = 1.2) {
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> faces;
  auto vertex = [&](const Eigen::Vector3d& p) {
    for (int i = 0; i < static_cast<int>(verts.size()); ++i)
      if ((verts[i] - p).norm() < 1e-12) return i;
    verts.push_back(p);
    return static_cast<int>(verts.size()) - 1;
  };
  const Eigen::Vector3d size(sx, sy, sz);
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto at = [&](int a, int b) {
            Eigen::Vector3d p;
            p[axis] = side * size[axis];
            p[u] = size[u] * a / n;
            p[v] = size[v] * b / n;
            return vertex(p);
          };
          const int p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          // (u, v, axis) is right-handed, so u x v = +axis: flip on the low side.
          if (side == 1) {
            faces.emplace_back(p00, p10, p11);
            faces.emplace_back(p00, p11, p01);
          } else {
            faces.emplace_back(p00, p11, p10);
            faces.emplace_back(p00, p01, p11);
          }
        }
      }
    }
  }
  return from_lists(verts, faces);
}

Mesh from_lists(const std::vector<Eigen::Vector3d>& verts, const std::vector<Eigen::Vector3i>& faces) {
  Mesh mesh;
  mesh.V.resize(verts.size(), 3);
  for (int i = 0; i < static_cast<int>(verts.size()); ++i) mesh.V.row(i) = verts[i].transpose();
  mesh.F.resize(faces.size(), 3);
  for (int i = 0; i < static_cast<int>(faces.size()); ++i) mesh.F.row(i) = faces[i].transpose();
  mesh.face_node = Eigen::VectorXi::Constant(mesh.num_faces(), -1);
  mesh.face_material = Eigen::VectorXi::Constant(mesh.num_faces(), -1);
  mesh.face_back_material = Eigen::VectorXi::Constant(mesh.num_faces(), -1);
  return mesh;
}

}  // namespace

TEST(AutomaticNodes, box_splits_into_its_six_sides) {
  Mesh mesh = grid_box(4);
  assign_automatic_nodes(mesh);
  ASSERT_EQ(mesh.node_names.size(), 6u);
  EXPECT_EQ(mesh.node_names.front(), "node_000");
  EXPECT_EQ(mesh.node_names.back(), "node_005");
  // Every side (32 consecutive faces) is exactly one node.
  std::set<int> seen;
  for (int side = 0; side < 6; ++side) {
    const int node = mesh.face_node[side * 32];
    for (int f = side * 32; f < (side + 1) * 32; ++f) ASSERT_EQ(mesh.face_node[f], node) << "face " << f;
    seen.insert(node);
  }
  EXPECT_EQ(seen.size(), 6u);
}

namespace {

// Appends `other` to `mesh` (no welding), shifted by `offset`.
void append(Mesh& mesh, const Mesh& other, const Eigen::Vector3d& offset) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  Mesh out;
  out.V.resize(nv + other.num_vertices(), 3);
  out.V << mesh.V, other.V.rowwise() + offset.transpose();
  out.F.resize(nf + other.num_faces(), 3);
  out.F << mesh.F, other.F.array() + nv;
  out.face_node = Eigen::VectorXi::Constant(out.num_faces(), -1);
  out.face_material = Eigen::VectorXi::Constant(out.num_faces(), -1);
  out.face_back_material = Eigen::VectorXi::Constant(out.num_faces(), -1);
  mesh = out;
}

int count_nodes_used(const Mesh& mesh) {
  std::set<int> used(mesh.face_node.data(), mesh.face_node.data() + mesh.face_node.size());
  return static_cast<int>(used.size());
}

}  // namespace

TEST(AutomaticNodes, rerun_gives_identical_assignment) {
  Mesh a = grid_box(6, 2.0, 1.0, 0.5);
  Mesh b = a;
  assign_automatic_nodes(a);
  assign_automatic_nodes(b);
  EXPECT_TRUE((a.face_node.array() == b.face_node.array()).all());
  EXPECT_EQ(a.node_names, b.node_names);
}

TEST(AutomaticNodes, nodes_are_numbered_in_order_of_their_first_face) {
  Mesh mesh = grid_box(3);
  assign_automatic_nodes(mesh);
  int next = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    ASSERT_LE(mesh.face_node[f], next) << "face " << f;
    if (mesh.face_node[f] == next) ++next;
  }
  EXPECT_EQ(next, 6);
}

TEST(AutomaticNodes, cap_merges_smallest_nodes_first) {
  // Box 1 x 1 x 0.1: two 1 m^2 sides and four 0.1 m^2 rims; a cap of 2 keeps the big sides
  // apart and merges the rims into them.
  Mesh mesh = grid_box(4, 1.0, 1.0, 0.1);
  AutomaticNodeOptions options;
  options.max_nodes = 2;
  assign_automatic_nodes(mesh, options);
  ASSERT_EQ(mesh.node_names.size(), 2u);
  // The z sides are the faces 128..191 (axis 2): low side then high side, 32 faces each.
  EXPECT_NE(mesh.face_node[128], mesh.face_node[160]);
  for (int f = 128; f < 160; ++f) ASSERT_EQ(mesh.face_node[f], mesh.face_node[128]);
  for (int f = 160; f < 192; ++f) ASSERT_EQ(mesh.face_node[f], mesh.face_node[160]);
}

TEST(AutomaticNodes, cap_of_one_gives_one_node) {
  Mesh mesh = grid_box(2);
  AutomaticNodeOptions options;
  options.max_nodes = 1;
  assign_automatic_nodes(mesh, options);
  EXPECT_EQ(mesh.node_names, std::vector<std::string>{"node_000"});
  EXPECT_TRUE((mesh.face_node.array() == 0).all());
}

TEST(AutomaticNodes, small_region_merges_into_neighbour_sharing_the_longest_edge) {
  // Box 1 x 1 x 0.01 (rims of 1% of a side): with the default 0.2% threshold the rims
  // (0.5% of the area each) survive; at 1% they merge into a big side, whose shared edge is
  // the rim's long edge.
  Mesh mesh = grid_box(2, 1.0, 1.0, 0.01);
  assign_automatic_nodes(mesh);
  EXPECT_EQ(mesh.node_names.size(), 6u);
  AutomaticNodeOptions options;
  options.min_node_area_fraction = 0.01;
  assign_automatic_nodes(mesh, options);
  EXPECT_EQ(mesh.node_names.size(), 2u);
}

TEST(AutomaticNodes, tiny_separate_component_joins_the_nearest_node) {
  // A 1 cm cube floating 5 cm above the +z side of a 1 m cube: its own component, too small
  // to be a node, so it joins the region whose bounding box is nearest (the +z side).
  Mesh mesh = grid_box(2, 1.0, 1.0, 1.0);
  const int big_faces = mesh.num_faces();
  append(mesh, grid_box(1, 0.01, 0.01, 0.01), Eigen::Vector3d(0.5, 0.5, 1.05));
  assign_automatic_nodes(mesh);
  ASSERT_EQ(mesh.node_names.size(), 6u);
  const int top = mesh.face_node[5 * 8];  // axis 2, high side: faces 40..47
  for (int f = big_faces; f < mesh.num_faces(); ++f) EXPECT_EQ(mesh.face_node[f], top) << "face " << f;
}

TEST(AutomaticNodes, large_separate_components_stay_separate) {
  Mesh mesh = grid_box(1);
  append(mesh, grid_box(1), Eigen::Vector3d(3.0, 0.0, 0.0));
  AutomaticNodeOptions options;
  options.max_normal_deviation_deg = 180.0;  // no planarity split: one region per component
  assign_automatic_nodes(mesh, options);
  ASSERT_EQ(mesh.node_names.size(), 2u);
  EXPECT_NE(mesh.face_node[0], mesh.face_node[12]);
}

TEST(AutomaticNodes, curved_surface_splits_by_normal_deviation) {
  // Open cylinder (radius 1, height 0.2) of 72 facets around: normals sweep 360 deg, so a
  // 30 deg limit (60 deg per region at best) needs at least 6 nodes and at most 12.
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> faces;
  const int n = 72;
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * 3.14159265358979323846 * i / n;
    verts.emplace_back(std::cos(phi), std::sin(phi), 0.0);
    verts.emplace_back(std::cos(phi), std::sin(phi), 0.2);
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    faces.emplace_back(2 * i, 2 * j, 2 * j + 1);
    faces.emplace_back(2 * i, 2 * j + 1, 2 * i + 1);
  }
  Mesh mesh = from_lists(verts, faces);
  assign_automatic_nodes(mesh);
  EXPECT_GE(mesh.node_names.size(), 6u);
  EXPECT_LE(mesh.node_names.size(), 12u);
}

TEST(AutomaticNodes, degenerate_faces_get_a_node_too) {
  Mesh mesh = grid_box(1);
  // A zero-area sliver on an existing edge.
  Mesh sliver = from_lists({mesh.V.row(mesh.F(0, 0)), mesh.V.row(mesh.F(0, 1)),
                            0.5 * (mesh.V.row(mesh.F(0, 0)) + mesh.V.row(mesh.F(0, 1)))},
                           {Eigen::Vector3i(0, 1, 2)});
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  append(mesh, sliver, zero);
  assign_automatic_nodes(mesh);
  EXPECT_GE(mesh.face_node.minCoeff(), 0);
  EXPECT_EQ(mesh.node_names.size(), 6u);
}

TEST(AutomaticNodes, bad_options_and_empty_mesh_are_rejected) {
  Mesh empty;
  EXPECT_THROW(assign_automatic_nodes(empty), InvalidInput);
  Mesh mesh = grid_box(1);
  AutomaticNodeOptions options;
  options.max_nodes = 0;
  EXPECT_THROW(assign_automatic_nodes(mesh, options), InvalidInput);
  options = {};
  options.max_normal_deviation_deg = 0.0;
  EXPECT_THROW(assign_automatic_nodes(mesh, options), InvalidInput);
  options = {};
  options.min_node_area_fraction = 1.0;
  EXPECT_THROW(assign_automatic_nodes(mesh, options), InvalidInput);
  Mesh with_nan = mesh;
  with_nan.V(2, 1) = std::nan("");
  EXPECT_THROW(assign_automatic_nodes(with_nan), InvalidInput);
  mesh.F(3, 1) = 999;
  EXPECT_THROW(assign_automatic_nodes(mesh), InvalidInput);
}

// --- real meshes ------------------------------------------------------------------------

TEST(SharedModelsAutomaticNodes, nasa_models_are_broken_down_deterministically) {
  const std::filesystem::path dir = std::filesystem::path(THERMODEC_SHARED_DIR) / "models" / "nasa";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << dir << " is absent";
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".stl") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) GTEST_SKIP() << "no .stl in " << dir;
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    const Mesh input = read_mesh(file);
    Mesh a = input, b = input;
    const auto start = std::chrono::steady_clock::now();
    assign_automatic_nodes(a);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    assign_automatic_nodes(b);
    ASSERT_EQ(a.face_node.size(), input.num_faces());
    EXPECT_GE(a.face_node.minCoeff(), 0);
    EXPECT_LT(a.face_node.maxCoeff(), static_cast<int>(a.node_names.size()));
    EXPECT_EQ(count_nodes_used(a), static_cast<int>(a.node_names.size()));
    EXPECT_LE(a.node_names.size(), 64u);
    EXPECT_GE(a.node_names.size(), 2u);
    EXPECT_TRUE((a.face_node.array() == b.face_node.array()).all());
    EXPECT_EQ(a.node_names, b.node_names);
    // Measured ~15 ms for 20k faces in Release; 2 s leaves room for Debug and a busy machine.
    EXPECT_LT(seconds, 2.0);
    std::cout << file.filename().string() << ": " << input.num_faces() << " faces -> "
              << a.node_names.size() << " nodes in " << seconds * 1e3 << " ms\n";
  }
}

TEST(SampleSatellite, obj_groups_are_the_thirteen_thermal_nodes) {
  const std::filesystem::path dir = std::filesystem::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite";
  const std::set<std::string> expected{"body_px", "body_mx", "body_py", "body_my", "body_pz",
                                       "body_mz", "yoke_py", "wing_py", "yoke_my", "wing_my",
                                       "boom",    "dish",    "instrument"};
  for (const char* name : {"satellite.obj", "satellite_dense.obj"}) {
    SCOPED_TRACE(name);
    const Mesh mesh = read_mesh(dir / name);
    EXPECT_EQ(std::set<std::string>(mesh.node_names.begin(), mesh.node_names.end()), expected);
    EXPECT_GE(mesh.face_node.minCoeff(), 0);
    EXPECT_EQ(count_nodes_used(mesh), 13);
    const std::set<std::string> materials(mesh.material_names.begin(), mesh.material_names.end());
    EXPECT_EQ(materials, (std::set<std::string>{"white_paint", "mli_kapton", "osr", "solar_cell", "black_paint"}));
    EXPECT_GE(mesh.face_material.minCoeff(), 0);
  }
  EXPECT_EQ(read_mesh(dir / "satellite.obj").num_faces(), 882);
  EXPECT_EQ(read_mesh(dir / "satellite_dense.obj").num_faces(), 19696);
}

TEST(SampleSatellite, automatic_breakdown_finds_each_body_side) {
  // Without its groups, the flat body sides must come out as whole nodes: every face of a
  // body panel lands in one automatic node, and different sides in different nodes.
  const std::filesystem::path file =
      std::filesystem::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite" / "satellite.obj";
  const Mesh grouped = read_mesh(file);
  Mesh mesh = grouped;
  assign_automatic_nodes(mesh);
  std::set<int> body_nodes;
  for (const std::string side : {"body_px", "body_mx", "body_py", "body_my", "body_pz", "body_mz"}) {
    const int group = static_cast<int>(
        std::find(grouped.node_names.begin(), grouped.node_names.end(), side) - grouped.node_names.begin());
    std::set<int> nodes;
    for (int f = 0; f < grouped.num_faces(); ++f)
      if (grouped.face_node[f] == group) nodes.insert(mesh.face_node[f]);
    EXPECT_EQ(nodes.size(), 1u) << side;
    body_nodes.insert(nodes.begin(), nodes.end());
  }
  EXPECT_EQ(body_nodes.size(), 6u);
}

TEST(SampleSatellite, model_files_load_with_thermal_data_for_every_node) {
  const std::filesystem::path dir = std::filesystem::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite";
  for (const char* name : {"model.json", "model_dense.json"}) {
    SCOPED_TRACE(name);
    const ThermalModel model = load_model(dir / name);
    ASSERT_EQ(model.nodes.size(), 13u);
    EXPECT_EQ(model.materials.size(), 5u);
    EXPECT_EQ(model.conductances.size(), 19u);  // 12 body edges + 7 appendage links
    double power_W = 0.0;
    for (const Node& node : model.nodes) {
      EXPECT_GT(node.capacitance_J_per_K, 0.0) << node.name;
      power_W += node.power_W;
    }
    EXPECT_DOUBLE_EQ(power_W, 210.0);
    EXPECT_EQ(model.environment.type, EnvironmentType::orbit);
    EXPECT_EQ(model.analysis.type, AnalysisType::transient_orbit);
    // Thin sheets (wings, yokes, dish) are two-sided, the closed body is not.
    const Mesh& mesh = model.mesh;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const std::string& node = mesh.node_names[mesh.face_node[f]];
      const bool sheet = node.rfind("wing", 0) == 0 || node.rfind("yoke", 0) == 0 || node == "dish";
      ASSERT_EQ(mesh.is_two_sided(f), sheet) << "face " << f << " of " << node;
    }
  }
}
