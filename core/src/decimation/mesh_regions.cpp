// The node and interface constraints of a mesh before any collapse: regions (faces of one
// node, material and back material), contour edges (between regions, open or non-manifold)
// and the vertex classes they give (free, on one contour, frozen), and the parts joined by
// manifold edges whose enclosed volume is kept. The classes are invariant under the collapses
// decimate_nodes allows, so they are computed once.
#include <algorithm>
#include <map>
#include <numeric>
#include <tuple>

#include "collapse_types.h"

namespace thermodec::collapse {
namespace {

void assign_regions(const Mesh& mesh, const NodeGroups& group_of, Context& c) {
  const int nf = mesh.num_faces();
  // Regions: distinct (node, material, back material), numbered in order of first face.
  std::map<std::tuple<int, int, int>, int> region_id;
  c.face_region.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const auto key = std::make_tuple(group_of(f), attr(mesh.face_material, f), attr(mesh.face_back_material, f));
    auto it = region_id.emplace(key, static_cast<int>(region_id.size())).first;
    c.face_region[f] = it->second;
  }
  c.region_node.resize(region_id.size());
  for (const auto& [key, id] : region_id) c.region_node[id] = std::get<0>(key);
  c.region_faces.assign(region_id.size(), 0);
  for (int f = 0; f < nf; ++f) ++c.region_faces[c.face_region[f]];
}

  // Non-manifold vertices: the faces around a vertex must form one fan (connected through
  // edges at that vertex with exactly two faces).
void freeze_nonmanifold_vertices(const Mesh& mesh, std::vector<char>& frozen) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::vector<std::vector<int>> vf(nv);
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) vf[mesh.F(f, j)].push_back(f);
  std::vector<int> local;
  for (int v = 0; v < nv; ++v) {
    const auto& fs = vf[v];
    if (fs.size() <= 1 || frozen[v]) continue;
    // Union faces around v that share an edge (v, w).
    local.resize(fs.size());
    std::iota(local.begin(), local.end(), 0);
    auto lfind = [&local](int x) {
      while (local[x] != x) x = local[x] = local[local[x]];
      return x;
    };
    for (size_t p = 0; p < fs.size(); ++p)
      for (size_t q = p + 1; q < fs.size(); ++q) {
        int shared = 0;
        for (int s = 0; s < 3; ++s)
          for (int t = 0; t < 3; ++t)
            if (mesh.F(fs[p], s) == mesh.F(fs[q], t)) ++shared;
        if (shared >= 2) local[lfind(static_cast<int>(p))] = lfind(static_cast<int>(q));
      }
    int fans = 0;
    for (size_t p = 0; p < fs.size(); ++p) fans += lfind(static_cast<int>(p)) == static_cast<int>(p);
    if (fans > 1) frozen[v] = 1;
  }
}

}  // namespace

int classify_mesh(const Mesh& mesh, const NodeGroups& group_of, Context& c) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  assign_regions(mesh, group_of, c);

  // Edges -> faces, to classify edges and vertices once (the classes are invariant under the
  // collapses allowed below, so they are never recomputed).
  struct EdgeFace {
    int a, b, f;
    bool operator<(const EdgeFace& o) const { return std::tie(a, b, f) < std::tie(o.a, o.b, o.f); }
  };
  std::vector<EdgeFace> ef;
  ef.reserve(3 * nf);
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) {
      const int a = mesh.F(f, j), b = mesh.F(f, (j + 1) % 3);
      ef.push_back({std::min(a, b), std::max(a, b), f});
    }
  std::sort(ef.begin(), ef.end());
  std::vector<int> contour_edges_at(nv, 0);
  std::vector<char> frozen(nv, 0);
  // Parts: faces connected across manifold edges (exactly two faces), so that a fin standing
  // on a closed box (a non-manifold edge) does not make the box "open". A part is closed when
  // each of its edges is shared by exactly two of its faces; its enclosed volume is then kept.
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&parent](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<char> face_on_open_edge(nf, 0);
  for (size_t i = 0; i < ef.size();) {
    size_t j = i;
    while (j < ef.size() && ef[j].a == ef[i].a && ef[j].b == ef[i].b) ++j;
    const int count = static_cast<int>(j - i);
    bool differ = false;
    const EdgeFace first = ef[i];
    for (auto it = ef.begin() + static_cast<std::ptrdiff_t>(i) + 1; it != ef.begin() + static_cast<std::ptrdiff_t>(j); ++it) {
      differ |= c.face_region[it->f] != c.face_region[first.f];
      if (count == 2) parent[find(it->f)] = find(first.f);
    }
    if (count != 2 || differ) {
      ++contour_edges_at[ef[i].a];
      ++contour_edges_at[ef[i].b];
    }
    if (count > 2 || ef[i].a == ef[i].b) frozen[ef[i].a] = frozen[ef[i].b] = 1;
    i = j;
  }
  for (size_t i = 0; i < ef.size();) {
    size_t j = i;
    while (j < ef.size() && ef[j].a == ef[i].a && ef[j].b == ef[i].b) ++j;
    for (size_t k = i; k < j; ++k) {
      int same_part = 0;
      for (size_t l = i; l < j; ++l) same_part += find(ef[l].f) == find(ef[k].f);
      if (same_part != 2) face_on_open_edge[ef[k].f] = 1;
    }
    i = j;
  }
  freeze_nonmanifold_vertices(mesh, frozen);
  for (size_t v = 0; v < c.contact_frozen.size() && v < frozen.size(); ++v) frozen[v] |= c.contact_frozen[v];
  c.vclass.resize(nv);
  for (int v = 0; v < nv; ++v) {
    const int k = contour_edges_at[v];
    c.vclass[v] = frozen[v] || k == 1 || k >= 3 ? kFrozen : k == 2 ? kContour : kFree;
  }

  // Components numbered by smallest face index (deterministic); closed = no open edge.
  c.face_component.resize(nf);
  std::vector<int> comp_of_root(nf, -1);
  int ncomp = 0;
  for (int f = 0; f < nf; ++f) {
    const int r = find(f);
    if (comp_of_root[r] < 0) comp_of_root[r] = ncomp++;
    c.face_component[f] = comp_of_root[r];
  }
  c.comp_closed.assign(ncomp, 1);
  c.comp_volume0.assign(ncomp, 0.0);
  c.comp_area0.assign(ncomp, 0.0);
  for (int f = 0; f < nf; ++f) {
    if (face_on_open_edge[f]) c.comp_closed[c.face_component[f]] = 0;
    const Vec3 p0 = mesh.V.row(mesh.F(f, 0)), p1 = mesh.V.row(mesh.F(f, 1)), p2 = mesh.V.row(mesh.F(f, 2));
    c.comp_volume0[c.face_component[f]] += p0.dot(p1.cross(p2)) / 6.0;
    c.comp_area0[c.face_component[f]] += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  c.comp_volume = c.comp_volume0;
  return ncomp;
}

}  // namespace thermodec::collapse
