#include "thermodec/nodes/automatic_nodes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/mesh/face_geometry.h"

// Why this shape: a thermal node should be a piece of surface that sees roughly one
// environment (one orientation) and conducts internally, so regions are grown over shared
// edges (conduction paths) and limited by the normal deviation from their seed (radiative
// orientation). Seeds are taken largest face first, so big flat panels become whole nodes
// before slivers at their borders start their own regions. Everything iterates over sorted
// vectors or ordered maps: the result depends only on the mesh, never on hash order.

namespace thermodec {
namespace {

struct FaceGeometry {
  Eigen::MatrixXd unit_normal;  // #F x 3, zero rows for degenerate faces
  Eigen::VectorXd area_m2;      // #F
};

// Undirected edges with the faces using them, sorted by vertex pair. Non-manifold edges
// (more than two faces) connect every pair of their faces.
struct EdgeFaces {
  std::int64_t key;  // min vertex * nv + max vertex
  int face;
};

std::vector<EdgeFaces> sorted_edge_faces(const Mesh& mesh) {
  const int nf = mesh.num_faces();
  const std::int64_t nv = mesh.num_vertices();
  std::vector<EdgeFaces> edges;
  edges.reserve(static_cast<size_t>(nf) * 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      if (a == b) continue;
      edges.push_back({std::min(a, b) * nv + std::max(a, b), f});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeFaces& x, const EdgeFaces& y) {
    return std::tie(x.key, x.face) < std::tie(y.key, y.face);
  });
  return edges;
}

// Edges shared by more faces than this (a "book" of sheets on one spine) are not expanded into
// face-to-face links, whose number grows with the square of the faces on the edge (10 000
// sheets would need 10^8 links, gigabytes from a 400 KB file). Such an edge becomes a hub that
// region growing crosses once per region, so memory stays linear in the faces.
constexpr std::size_t kMaxLinkedFacesPerEdge = 16;

// Compressed face adjacency (CSR), each neighbour list sorted and without duplicates, with
// the shared edge's length [m]; plus the hub edges (see kMaxLinkedFacesPerEdge), each with
// its faces in ascending order and its length [m].
struct FaceAdjacency {
  std::vector<int> offset;  // #F + 1
  std::vector<int> neighbour;
  std::vector<double> edge_length_m;
  std::vector<int> hub_offset;  // #hubs + 1, into hub_face
  std::vector<int> hub_face;
  std::vector<double> hub_length_m;
  std::vector<int> face_hub_offset;  // #F + 1, into face_hub
  std::vector<int> face_hub;
};

FaceAdjacency face_adjacency(const Mesh& mesh, const std::vector<EdgeFaces>& edges) {
  const int nf = mesh.num_faces();
  const std::int64_t nv = mesh.num_vertices();
  struct Link {
    int from, to;
    double length;
  };
  std::vector<Link> links;
  links.reserve(edges.size());
  FaceAdjacency adj;
  adj.hub_offset.push_back(0);
  std::vector<std::pair<int, int>> face_hub_pairs;  // (face, hub)
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i > 1) {
      const int a = static_cast<int>(edges[i].key / nv), b = static_cast<int>(edges[i].key % nv);
      const double length = (mesh.V.row(a) - mesh.V.row(b)).norm();
      if (j - i <= kMaxLinkedFacesPerEdge) {
        for (size_t p = i; p < j; ++p)
          for (size_t q = i; q < j; ++q)
            if (edges[p].face != edges[q].face) links.push_back({edges[p].face, edges[q].face, length});
      } else {
        const int hub = static_cast<int>(adj.hub_length_m.size());
        for (size_t p = i; p < j; ++p) {
          if (p > i && edges[p].face == edges[p - 1].face) continue;
          adj.hub_face.push_back(edges[p].face);
          face_hub_pairs.push_back({edges[p].face, hub});
        }
        adj.hub_offset.push_back(static_cast<int>(adj.hub_face.size()));
        adj.hub_length_m.push_back(length);
      }
    }
    i = j;
  }
  std::sort(links.begin(), links.end(), [](const Link& x, const Link& y) {
    return std::tie(x.from, x.to) < std::tie(y.from, y.to);
  });
  adj.offset.assign(nf + 1, 0);
  for (size_t i = 0; i < links.size();) {
    // Two faces sharing two edges (a folded pair) count once, with both lengths summed.
    size_t j = i;
    double length = 0.0;
    while (j < links.size() && links[j].from == links[i].from && links[j].to == links[i].to) {
      length += links[j].length;
      ++j;
    }
    adj.neighbour.push_back(links[i].to);
    adj.edge_length_m.push_back(length);
    ++adj.offset[links[i].from + 1];
    i = j;
  }
  for (int f = 0; f < nf; ++f) adj.offset[f + 1] += adj.offset[f];
  std::sort(face_hub_pairs.begin(), face_hub_pairs.end());
  adj.face_hub_offset.assign(nf + 1, 0);
  for (const auto& [face, hub] : face_hub_pairs) {
    adj.face_hub.push_back(hub);
    ++adj.face_hub_offset[face + 1];
  }
  for (int f = 0; f < nf; ++f) adj.face_hub_offset[f + 1] += adj.face_hub_offset[f];
  return adj;
}

// Region growing inside the edge-connected components: BFS from the largest unassigned face,
// accepting neighbours whose normal is within the angle of the seed's normal. Degenerate faces
// have no orientation and join whichever region reaches them first.
std::vector<int> grow_planar_regions(const FaceGeometry& geom, const FaceAdjacency& adj,
                                     double cos_max_deviation, int& num_regions) {
  const int nf = static_cast<int>(geom.area_m2.size());
  std::vector<int> order(nf);
  for (int f = 0; f < nf; ++f) order[f] = f;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return geom.area_m2[a] > geom.area_m2[b]; });
  std::vector<int> region(nf, -1);
  std::vector<int> hub_region(adj.hub_length_m.size(), -1);
  std::vector<int> queue;
  queue.reserve(nf);
  num_regions = 0;
  for (const int seed : order) {
    if (region[seed] >= 0) continue;
    const int r = num_regions++;
    const Eigen::Vector3d seed_normal = geom.unit_normal.row(seed).transpose();
    const bool seed_degenerate = seed_normal.squaredNorm() == 0.0;
    queue.clear();
    queue.push_back(seed);
    region[seed] = r;
    for (size_t head = 0; head < queue.size(); ++head) {
      const int f = queue[head];
      auto visit = [&](int g) {
        if (region[g] >= 0) return;
        const Eigen::Vector3d n = geom.unit_normal.row(g).transpose();
        const bool g_degenerate = n.squaredNorm() == 0.0;
        // A degenerate seed (only when every bigger face is taken) collects degenerate
        // neighbours only, so it cannot swallow an oriented region.
        const bool accept = seed_degenerate ? g_degenerate
                                            : (g_degenerate || seed_normal.dot(n) >= cos_max_deviation);
        if (!accept) return;
        region[g] = r;
        queue.push_back(g);
      };
      for (int k = adj.offset[f]; k < adj.offset[f + 1]; ++k) visit(adj.neighbour[k]);
      // Acceptance depends only on the seed's normal, so one pass over a hub per region suffices.
      for (int k = adj.face_hub_offset[f]; k < adj.face_hub_offset[f + 1]; ++k) {
        const int h = adj.face_hub[k];
        if (hub_region[h] == r) continue;
        hub_region[h] = r;
        for (int i = adj.hub_offset[h]; i < adj.hub_offset[h + 1]; ++i) visit(adj.hub_face[i]);
      }
    }
  }
  return region;
}

struct Region {
  double area_m2 = 0.0;
  Eigen::Vector3d box_min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d box_max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  std::map<int, double> shared_edge_m;  // neighbour region -> summed shared edge length
  int merged_into = -1;                 // -1 = alive
};

double box_gap_m(const Region& a, const Region& b) {
  const Eigen::Vector3d gap =
      (a.box_min - b.box_max).cwiseMax(b.box_min - a.box_max).cwiseMax(0.0);
  return gap.norm();
}

// Merges small regions, then enforces the node cap, always smallest region first into the
// neighbour sharing the longest edge (the strongest conduction path). A region with no edge
// neighbour (a separate component, e.g. a bolt or a loose panel) joins the region whose
// bounding box is closest: it is most likely mounted there.
void merge_regions(std::vector<Region>& regions, double min_area_m2, int max_nodes) {
  using Entry = std::pair<double, int>;  // (area, region): smallest area first, then lowest id
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  int alive = static_cast<int>(regions.size());
  for (int r = 0; r < alive; ++r) heap.push({regions[r].area_m2, r});
  while (!heap.empty()) {
    const auto [area, r] = heap.top();
    heap.pop();
    Region& small = regions[r];
    if (small.merged_into >= 0 || area != small.area_m2) continue;  // stale entry
    if (area >= min_area_m2 && alive <= max_nodes) break;
    if (alive == 1) break;
    int target = -1;
    double best = -1.0;
    for (const auto& [n, length] : small.shared_edge_m)
      if (length > best) best = length, target = n;  // ties: lowest id (map order)
    if (target < 0) {
      double best_gap = std::numeric_limits<double>::infinity();
      for (int n = 0; n < static_cast<int>(regions.size()); ++n) {
        if (n == r || regions[n].merged_into >= 0) continue;
        const double gap = box_gap_m(small, regions[n]);
        if (gap < best_gap) best_gap = gap, target = n;
      }
    }
    Region& big = regions[target];
    for (const auto& [n, length] : small.shared_edge_m) {
      auto& other = regions[n].shared_edge_m;
      other.erase(r);
      if (n == target) continue;
      big.shared_edge_m[n] += length;
      other[target] += length;
    }
    small.shared_edge_m.clear();
    big.area_m2 += small.area_m2;
    big.box_min = big.box_min.cwiseMin(small.box_min);
    big.box_max = big.box_max.cwiseMax(small.box_max);
    small.merged_into = target;
    --alive;
    heap.push({big.area_m2, target});
  }
}

// Final surviving region of every region (merge chains resolved once, with path compression).
std::vector<int> final_regions(const std::vector<Region>& regions) {
  std::vector<int> root(regions.size(), -1);
  std::vector<int> path;
  for (int r = 0; r < static_cast<int>(regions.size()); ++r) {
    int x = r;
    path.clear();
    while (root[x] < 0 && regions[x].merged_into >= 0) {
      path.push_back(x);
      x = regions[x].merged_into;
    }
    const int top = root[x] >= 0 ? root[x] : x;
    root[x] = top;
    for (const int p : path) root[p] = top;
  }
  return root;
}

}  // namespace

void assign_automatic_nodes(Mesh& mesh, const AutomaticNodeOptions& options) {
  const int nf = mesh.num_faces();
  if (nf == 0) throw InvalidInput("automatic nodes: the mesh has no faces");
  if (options.max_nodes < 1)
    throw InvalidInput("automatic nodes: max_nodes must be >= 1, got " + std::to_string(options.max_nodes));
  if (!(options.max_normal_deviation_deg > 0.0 && options.max_normal_deviation_deg <= 180.0))
    throw InvalidInput("automatic nodes: max_normal_deviation_deg must be in (0, 180], got " +
                       std::to_string(options.max_normal_deviation_deg));
  if (!(options.min_node_area_fraction >= 0.0 && options.min_node_area_fraction < 1.0))
    throw InvalidInput("automatic nodes: min_node_area_fraction must be in [0, 1), got " +
                       std::to_string(options.min_node_area_fraction));
  if (mesh.F.cols() != 3) throw InvalidInput("automatic nodes: faces must be triangles");
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= mesh.num_vertices())
        throw InvalidInput("automatic nodes: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(mesh.F(f, k)) + " outside [0, " +
                           std::to_string(mesh.num_vertices()) + ")");

  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (!mesh.V.row(v).allFinite())
      throw InvalidInput("automatic nodes: vertex " + std::to_string(v) + " has a non-finite coordinate");

  const FaceGeometry geom{face_normals(mesh.V, mesh.F), face_areas(mesh.V, mesh.F)};
  const std::vector<EdgeFaces> edges = sorted_edge_faces(mesh);
  const FaceAdjacency adj = face_adjacency(mesh, edges);

  // The cosine threshold is nudged by 1e-12 so that exactly coplanar triangles, whose
  // normals differ only by rounding, never split at 0 degrees.
  constexpr double kPi = 3.14159265358979323846;
  const double cos_max = std::cos(options.max_normal_deviation_deg * kPi / 180.0) - 1e-12;
  int num_regions = 0;
  const std::vector<int> face_region = grow_planar_regions(geom, adj, cos_max, num_regions);

  std::vector<Region> regions(num_regions);
  double total_area_m2 = 0.0;
  for (int f = 0; f < nf; ++f) {
    Region& r = regions[face_region[f]];
    r.area_m2 += geom.area_m2[f];
    total_area_m2 += geom.area_m2[f];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = mesh.V.row(mesh.F(f, k)).transpose();
      r.box_min = r.box_min.cwiseMin(p);
      r.box_max = r.box_max.cwiseMax(p);
    }
    for (int k = adj.offset[f]; k < adj.offset[f + 1]; ++k) {
      const int g = adj.neighbour[k];
      if (face_region[g] != face_region[f]) r.shared_edge_m[face_region[g]] += adj.edge_length_m[k];
    }
  }
  // A hub edge links each region on it to the region of its lowest face (linear, see
  // kMaxLinkedFacesPerEdge), with the edge length once per face on it.
  for (std::size_t h = 0; h < adj.hub_length_m.size(); ++h) {
    const int base = face_region[adj.hub_face[adj.hub_offset[h]]];
    for (int i = adj.hub_offset[h] + 1; i < adj.hub_offset[h + 1]; ++i) {
      const int other = face_region[adj.hub_face[i]];
      if (other == base) continue;
      regions[base].shared_edge_m[other] += adj.hub_length_m[h];
      regions[other].shared_edge_m[base] += adj.hub_length_m[h];
    }
  }
  merge_regions(regions, options.min_node_area_fraction * total_area_m2, options.max_nodes);

  // Nodes are numbered in order of their lowest face index, so the numbering follows the
  // file and does not depend on the growing order.
  const std::vector<int> root = final_regions(regions);
  std::vector<int> node_of_region(num_regions, -1);
  int num_nodes = 0;
  mesh.face_node.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const int r = root[face_region[f]];
    if (node_of_region[r] < 0) node_of_region[r] = num_nodes++;
    mesh.face_node[f] = node_of_region[r];
  }
  const int width = std::max<int>(3, static_cast<int>(std::to_string(num_nodes - 1).size()));
  mesh.node_names.assign(num_nodes, std::string());
  for (int n = 0; n < num_nodes; ++n) {
    std::string digits = std::to_string(n);
    mesh.node_names[n] = "node_" + std::string(width - digits.size(), '0') + digits;
  }
}

}  // namespace thermodec
