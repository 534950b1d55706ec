// Mesh repair: the preprocessing the paper applies before decimation (its Fig. 5: CAD
// tessellations are often non-conforming and non-manifold; they are made triangular and
// conforming by recursive edge bisection and conforming facet triangulation).
#include "thermodec/mesh/repair.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/mesh/weld.h"

namespace thermodec {
namespace {

using Vec3 = Eigen::Vector3d;
using Tri = std::array<int, 3>;

struct Work {
  std::vector<Vec3> v;
  std::vector<Tri> f;
  std::vector<int> src;      // input face of each face
  std::vector<char> flipped; // orientation differs from the input face's
};

int attr(const Eigen::VectorXi& a, int f) { return a.size() > f ? a[f] : -1; }

struct CellKey {
  long long x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  size_t operator()(const CellKey& k) const {
    return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
CellKey cell_of(const Vec3& p, double h) {
  return {static_cast<long long>(std::floor(p.x() / h)), static_cast<long long>(std::floor(p.y() / h)),
          static_cast<long long>(std::floor(p.z() / h))};
}

std::pair<int, int> ekey(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

std::map<std::pair<int, int>, std::vector<int>> edge_map(const Work& w) {
  std::map<std::pair<int, int>, std::vector<int>> e;
  for (size_t f = 0; f < w.f.size(); ++f)
    for (int j = 0; j < 3; ++j) e[ekey(w.f[f][j], w.f[f][(j + 1) % 3])].push_back(static_cast<int>(f));
  return e;
}

// Splits faces at vertices lying inside their open edges (T-junctions), recursively: the
// hanging vertex nearest an edge's midpoint bisects the face first, and the two halves inherit
// the remaining hanging vertices of their edges (the paper's recursive edge bisection).
int conform(Work& w, double tol) {
  const auto edges = edge_map(w);
  std::vector<int> open_vertices;
  double mean_len = 0;
  int n_open = 0;
  for (const auto& [e, fs] : edges)
    if (fs.size() == 1) {
      open_vertices.push_back(e.first);
      open_vertices.push_back(e.second);
      mean_len += (w.v[e.first] - w.v[e.second]).norm();
      ++n_open;
    }
  if (n_open == 0) return 0;
  std::sort(open_vertices.begin(), open_vertices.end());
  open_vertices.erase(std::unique(open_vertices.begin(), open_vertices.end()), open_vertices.end());
  const double h = std::max(mean_len / n_open, 10 * tol);
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  for (int v : open_vertices) grid[cell_of(w.v[v], h)].push_back(v);

  // Hanging vertices per (face, edge j = (f[j], f[j+1])), sorted by parameter along the edge.
  std::map<std::pair<int, int>, std::vector<int>> hanging;
  for (const auto& [e, fs] : edges) {
    if (fs.size() != 1) continue;
    const Vec3 a = w.v[e.first], b = w.v[e.second];
    const double len = (b - a).norm();
    if (!(len > 2 * tol)) continue;
    const CellKey lo = cell_of(a.cwiseMin(b) - Vec3::Constant(tol), h);
    const CellKey hi = cell_of(a.cwiseMax(b) + Vec3::Constant(tol), h);
    std::vector<std::pair<double, int>> on_edge;
    for (long long x = lo.x; x <= hi.x; ++x)
      for (long long y = lo.y; y <= hi.y; ++y)
        for (long long z = lo.z; z <= hi.z; ++z) {
          auto it = grid.find({x, y, z});
          if (it == grid.end()) continue;
          for (int p : it->second) {
            if (p == e.first || p == e.second) continue;
            const double t = (w.v[p] - a).dot(b - a) / (len * len);
            if (t * len <= tol || (1 - t) * len <= tol) continue;
            if ((w.v[p] - (a + t * (b - a))).norm() <= tol) on_edge.emplace_back(t, p);
          }
        }
    if (on_edge.empty()) continue;
    std::sort(on_edge.begin(), on_edge.end());
    const int f = fs[0];
    int j = 0;
    while (ekey(w.f[f][j], w.f[f][(j + 1) % 3]) != e) ++j;
    std::vector<int> list;
    for (const auto& tp : on_edge) list.push_back(tp.second);
    if (w.f[f][j] != e.first) std::reverse(list.begin(), list.end());  // order from f[j] to f[j+1]
    hanging[{f, j}] = list;
  }
  if (hanging.empty()) return 0;

  struct Pending {
    int face;
    std::array<std::vector<int>, 3> h;  // hanging vertices along edge j, ordered from f[j]
  };
  std::map<int, Pending> per_face;
  for (auto& [key, list] : hanging) {
    auto& p = per_face[key.first];
    p.face = key.first;
    p.h[key.second] = list;
  }
  int splits = 0;
  std::deque<Pending> queue;
  for (auto& [f, p] : per_face) queue.push_back(p);
  while (!queue.empty()) {
    Pending p = std::move(queue.front());
    queue.pop_front();
    const Tri t = w.f[p.face];
    // Pick the hanging vertex closest to the midpoint of its edge.
    int bj = -1, bk = -1;
    double best = 2;
    for (int j = 0; j < 3; ++j) {
      const auto& list = p.h[j];
      for (size_t k = 0; k < list.size(); ++k) {
        const double frac = (k + 1.0) / (list.size() + 1.0);
        if (std::abs(frac - 0.5) < best) best = std::abs(frac - 0.5), bj = j, bk = static_cast<int>(k);
      }
    }
    if (bj < 0) continue;
    const int a = t[bj], b = t[(bj + 1) % 3], c = t[(bj + 2) % 3];
    const int m = p.h[bj][bk];
    // Face (a, m, c) keeps the slot; (m, b, c) is appended.
    Pending left, right;
    left.face = p.face;
    right.face = static_cast<int>(w.f.size());
    w.f[p.face] = {a, m, c};
    w.f.push_back({m, b, c});
    w.src.push_back(w.src[p.face]);
    w.flipped.push_back(w.flipped[p.face]);
    left.h[0].assign(p.h[bj].begin(), p.h[bj].begin() + bk);       // a -> m
    left.h[2] = p.h[(bj + 2) % 3];                                  // c -> a
    right.h[0].assign(p.h[bj].begin() + bk + 1, p.h[bj].end());     // m -> b
    right.h[1] = p.h[(bj + 1) % 3];                                 // b -> c
    ++splits;
    for (Pending* q : {&left, &right})
      if (!q->h[0].empty() || !q->h[1].empty() || !q->h[2].empty()) queue.push_back(std::move(*q));
  }
  return splits;
}

void flip(Work& w, int f) {
  std::swap(w.f[f][1], w.f[f][2]);
  w.flipped[f] = !w.flipped[f];
}

// Breadth-first propagation across manifold edges from the lowest-index face of each
// component, then closed components are turned to enclose positive volume.
int orient(Work& w, int& conflicts) {
  const auto edges = edge_map(w);
  const int nf = static_cast<int>(w.f.size());
  std::vector<std::vector<int>> nbr(nf);
  for (const auto& [e, fs] : edges)
    if (fs.size() == 2) {
      nbr[fs[0]].push_back(fs[1]);
      nbr[fs[1]].push_back(fs[0]);
    }
  auto directed = [&](int f, int a, int b) {  // does f traverse a -> b?
    for (int j = 0; j < 3; ++j)
      if (w.f[f][j] == a && w.f[f][(j + 1) % 3] == b) return true;
    return false;
  };
  auto consistent = [&](int f, int g) {
    for (int j = 0; j < 3; ++j) {
      const int a = w.f[f][j], b = w.f[f][(j + 1) % 3];
      if (directed(g, a, b)) return false;
    }
    return true;
  };
  std::vector<int> comp(nf, -1);
  int ncomp = 0;
  for (int s = 0; s < nf; ++s) {
    if (comp[s] >= 0) continue;
    std::deque<int> q{s};
    comp[s] = ncomp;
    while (!q.empty()) {
      const int f = q.front();
      q.pop_front();
      for (int g : nbr[f]) {
        if (comp[g] < 0) {
          comp[g] = ncomp;
          if (!consistent(f, g)) flip(w, g);
          q.push_back(g);
        }
      }
    }
    ++ncomp;
  }
  conflicts = 0;
  for (const auto& [e, fs] : edges)
    if (fs.size() == 2 && !consistent(fs[0], fs[1])) ++conflicts;
  // Closed components (every edge with exactly two faces) should enclose positive volume.
  std::vector<char> closed(ncomp, 1);
  for (const auto& [e, fs] : edges)
    if (fs.size() != 2)
      for (int f : fs) closed[comp[f]] = 0;
  std::vector<double> volume(ncomp, 0.0);
  for (int f = 0; f < nf; ++f)
    volume[comp[f]] += w.v[w.f[f][0]].dot(w.v[w.f[f][1]].cross(w.v[w.f[f][2]]));
  for (int f = 0; f < nf; ++f)
    if (closed[comp[f]] && volume[comp[f]] < 0) flip(w, f);
  int flipped = 0;
  for (int f = 0; f < nf; ++f) flipped += w.flipped[f];
  return flipped;
}

int count_non_manifold_vertices(const Work& w) {
  std::vector<std::vector<int>> vf(w.v.size());
  for (size_t f = 0; f < w.f.size(); ++f)
    for (int k : w.f[f]) vf[k].push_back(static_cast<int>(f));
  int count = 0;
  std::vector<int> parent;
  for (size_t v = 0; v < w.v.size(); ++v) {
    const auto& fs = vf[v];
    if (fs.size() < 2) continue;
    parent.resize(fs.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    for (size_t p = 0; p < fs.size(); ++p)
      for (size_t q = p + 1; q < fs.size(); ++q) {
        int shared = 0;
        for (int s : w.f[fs[p]])
          for (int t : w.f[fs[q]]) shared += s == t;
        if (shared >= 2) parent[find(static_cast<int>(p))] = find(static_cast<int>(q));
      }
    int fans = 0;
    for (size_t p = 0; p < fs.size(); ++p) fans += find(static_cast<int>(p)) == static_cast<int>(p);
    count += fans > 1;
  }
  return count;
}

}  // namespace

std::string RepairReport::summary() const {
  std::ostringstream s;
  auto line = [&s](int n, const char* what) {
    if (n) s << what << ": " << n << "\n";
  };
  line(vertices_welded, "vertices welded");
  line(degenerate_faces_dropped, "degenerate faces dropped");
  line(duplicate_faces_dropped, "duplicate faces dropped");
  line(t_junctions_split, "T-junction edge bisections");
  line(faces_flipped, "faces flipped");
  line(unreferenced_vertices_removed, "unreferenced vertices removed");
  line(orientation_conflicts, "edges left with inconsistent orientation (non-orientable)");
  line(non_manifold_edges, "non-manifold edges (kept)");
  line(non_manifold_vertices, "non-manifold vertices (kept)");
  line(open_edges, "open boundary edges");
  if (!changed()) s << "no changes\n";
  return s.str();
}

RepairResult repair_mesh(const Mesh& mesh, const RepairOptions& o) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (!(o.relative_tolerance >= 0)) throw InvalidInput("repair: relative_tolerance must be >= 0");
  if (!mesh.V.allFinite()) throw InvalidInput("repair: vertex coordinates contain NaN or inf");
  if (mesh.face_node.size() != nf)
    throw InvalidInput("repair: face_node has " + std::to_string(mesh.face_node.size()) + " entries for " +
                       std::to_string(nf) + " faces");
  Work w;
  w.v.resize(nv);
  for (int i = 0; i < nv; ++i) w.v[i] = mesh.V.row(i).transpose();
  w.f.resize(nf);
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) {
      const int k = mesh.F(f, j);
      if (k < 0 || k >= nv)
        throw InvalidInput("repair: face " + std::to_string(f) + " has vertex index " + std::to_string(k) +
                           " outside [0, " + std::to_string(nv) + ")");
      w.f[f][j] = k;
    }
  w.src.resize(nf);
  std::iota(w.src.begin(), w.src.end(), 0);
  w.flipped.assign(nf, 0);

  double diag = 0;
  if (nv > 0) diag = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  const double tol = o.relative_tolerance * diag;
  RepairResult res;
  RepairReport& rep = res.report;

  if (o.weld && tol > 0) {
    const WeldResult welded = weld_vertices(mesh.V, tol);
    rep.vertices_welded = nv - static_cast<int>(welded.V.rows());
    w.v.resize(welded.V.rows());
    for (int i = 0; i < welded.V.rows(); ++i) w.v[i] = welded.V.row(i).transpose();
    for (auto& t : w.f)
      for (int& k : t) k = welded.new_index[k];
  }

  auto filter = [&w](const std::vector<char>& keep) {
    Work n;
    n.v = w.v;
    for (size_t f = 0; f < w.f.size(); ++f)
      if (keep[f]) {
        n.f.push_back(w.f[f]);
        n.src.push_back(w.src[f]);
        n.flipped.push_back(w.flipped[f]);
      }
    w = std::move(n);
  };
  if (o.drop_degenerate) {
    std::vector<char> keep(w.f.size(), 1);
    for (size_t f = 0; f < w.f.size(); ++f) {
      const Tri& t = w.f[f];
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
        keep[f] = 0;
        continue;
      }
      // Zero area: the height over the longest edge is below the tolerance (needles and caps;
      // a cap's middle vertex then becomes a T-junction that conforming heals).
      const Vec3 a = w.v[t[0]], b = w.v[t[1]], c = w.v[t[2]];
      const double twice_area = (b - a).cross(c - a).norm();
      const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
      if (!(twice_area > tol * longest)) keep[f] = 0;
    }
    rep.degenerate_faces_dropped = static_cast<int>(std::count(keep.begin(), keep.end(), 0));
    if (rep.degenerate_faces_dropped) filter(keep);
  }
  if (o.drop_duplicates) {
    std::vector<char> keep(w.f.size(), 1);
    std::set<Tri> seen;
    for (size_t f = 0; f < w.f.size(); ++f) {
      Tri t = w.f[f];
      std::sort(t.begin(), t.end());
      if (!seen.insert(t).second) keep[f] = 0;
    }
    rep.duplicate_faces_dropped = static_cast<int>(std::count(keep.begin(), keep.end(), 0));
    if (rep.duplicate_faces_dropped) filter(keep);
  }
  if (o.conform_t_junctions)
    for (int pass = 0; pass < 3; ++pass) {
      const int s = conform(w, tol);
      rep.t_junctions_split += s;
      if (s == 0) break;
    }
  if (o.orient) rep.faces_flipped = orient(w, rep.orientation_conflicts);

  // Compact vertices (first use order would renumber; keep input order instead).
  std::vector<int> used(w.v.size(), -1);
  for (const auto& t : w.f)
    for (int k : t) used[k] = 1;
  int nv_out = 0;
  for (auto& u : used) u = u > 0 ? nv_out++ : -1;
  rep.unreferenced_vertices_removed = static_cast<int>(w.v.size()) - nv_out;
  Mesh& out = res.mesh;
  out.V.resize(nv_out, 3);
  for (size_t i = 0; i < w.v.size(); ++i)
    if (used[i] >= 0) out.V.row(used[i]) = w.v[i].transpose();
  const int nf_out = static_cast<int>(w.f.size());
  out.F.resize(nf_out, 3);
  out.face_node.resize(nf_out);
  out.face_material.resize(nf_out);
  out.face_back_material.resize(nf_out);
  res.source_face.resize(nf_out);
  for (int f = 0; f < nf_out; ++f) {
    const int s = w.src[f];
    for (int j = 0; j < 3; ++j) out.F(f, j) = used[w.f[f][j]];
    out.face_node[f] = mesh.face_node[s];
    int front = attr(mesh.face_material, s), back = attr(mesh.face_back_material, s);
    if (w.flipped[f] && back >= 0 && front >= 0) std::swap(front, back);
    out.face_material[f] = front;
    out.face_back_material[f] = back;
    res.source_face[f] = s;
  }
  out.node_names = mesh.node_names;
  out.material_names = mesh.material_names;

  const auto edges = edge_map(w);
  for (const auto& [e, fs] : edges) {
    rep.non_manifold_edges += fs.size() > 2;
    rep.open_edges += fs.size() == 1;
  }
  rep.non_manifold_vertices = count_non_manifold_vertices(w);
  return res;
}

}  // namespace thermodec
