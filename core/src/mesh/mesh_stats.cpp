#include "thermodec/mesh/mesh_stats.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <set>

#include "thermodec/mesh/face_geometry.h"

namespace thermodec {
namespace {

struct EdgeUse {
  int a, b, face;
  bool operator<(const EdgeUse& o) const { return std::tie(a, b, face) < std::tie(o.a, o.b, o.face); }
};

// Undirected edges with the face using them, sorted so equal edges are adjacent.
std::vector<EdgeUse> sorted_edge_uses(const Eigen::MatrixXi& F) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * static_cast<std::size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a == b) continue;  // collapsed edge of a degenerate face
      uses.push_back({std::min(a, b), std::max(a, b), f});
    }
  std::sort(uses.begin(), uses.end());
  return uses;
}

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

int face_node_or_none(const Mesh& mesh, int f) { return mesh.face_node.size() > f ? mesh.face_node[f] : -1; }

}  // namespace

Eigen::VectorXi face_components(const Eigen::MatrixXi& F) {
  const int nf = static_cast<int>(F.rows());
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  const auto uses = sorted_edge_uses(F);
  for (std::size_t i = 1; i < uses.size(); ++i)
    if (uses[i].a == uses[i - 1].a && uses[i].b == uses[i - 1].b) {
      const int r1 = find_root(parent, uses[i].face), r2 = find_root(parent, uses[i - 1].face);
      if (r1 != r2) parent[std::max(r1, r2)] = std::min(r1, r2);  // root = lowest face
    }
  Eigen::VectorXi component(nf);
  std::vector<int> id_of_root(nf, -1);
  int next = 0;
  for (int f = 0; f < nf; ++f) {
    const int r = find_root(parent, f);
    if (id_of_root[r] < 0) id_of_root[r] = next++;
    component[f] = id_of_root[r];
  }
  return component;
}

MeshStats mesh_stats(const Mesh& mesh) {
  MeshStats s;
  s.faces = mesh.num_faces();
  s.vertices = mesh.num_vertices();
  std::vector<char> used(s.vertices, 0);
  for (int f = 0; f < s.faces; ++f)
    for (int k = 0; k < 3; ++k) used[mesh.F(f, k)] = 1;
  s.unreferenced_vertices = static_cast<int>(std::count(used.begin(), used.end(), 0));
  const auto uses = sorted_edge_uses(mesh.F);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
    ++s.edges;
    if (j - i == 1) ++s.boundary_edges;
    if (j - i > 2) ++s.non_manifold_edges;
    i = j;
  }
  const Eigen::VectorXi comp = face_components(mesh.F);
  s.components = s.faces ? comp.maxCoeff() + 1 : 0;
  s.degenerate_faces = static_cast<int>(degenerate_faces(mesh.V, mesh.F).size());
  s.area_m2 = face_areas(mesh.V, mesh.F).sum();
  return s;
}

std::vector<int> node_face_counts(const Mesh& mesh) {
  std::vector<int> counts(mesh.node_names.size(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int n = face_node_or_none(mesh, f);
    if (n >= 0 && n < static_cast<int>(counts.size())) ++counts[n];
  }
  return counts;
}

std::vector<double> node_areas_m2(const Mesh& mesh) {
  std::vector<double> areas(mesh.node_names.size(), 0.0);
  const Eigen::VectorXd a = face_areas(mesh.V, mesh.F);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int n = face_node_or_none(mesh, f);
    if (n >= 0 && n < static_cast<int>(areas.size())) areas[n] += a[f];
  }
  return areas;
}

std::vector<std::vector<int>> node_materials(const Mesh& mesh) {
  std::vector<std::set<int>> sets(mesh.node_names.size());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int n = face_node_or_none(mesh, f);
    if (n >= 0 && n < static_cast<int>(sets.size()))
      sets[n].insert(mesh.face_material.size() > f ? mesh.face_material[f] : -1);
  }
  std::vector<std::vector<int>> out;
  for (const auto& s : sets) out.emplace_back(s.begin(), s.end());
  return out;
}

}  // namespace thermodec
