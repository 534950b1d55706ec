// Node-preserving decimation on vcglib's local optimisation framework.
//
// References:
//  P. Lindstrom, G. Turk, "Fast and memory efficient polygonal simplification", IEEE Vis 1998
//    (volume preservation / volume optimisation / boundary / shape objectives, solved as a
//    hierarchy of linear constraints with the "alpha compatibility" test).
//  T. Dey, H. Edelsbrunner et al., "Topology preserving edge contraction", 1999 (link condition).
//
// Why our own collapse type instead of vcg's quadric one: the quadric metric does not preserve
// volume or node areas and treats node interfaces like any edge, so it opens cracks between
// nodes; here regions (node, material, back material) are hard constraints.
#include "thermodec/decimation/decimate_nodes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include <Eigen/Geometry>
#include <tuple>

#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/local_optimization.h>
#include <vcg/complex/algorithms/local_optimization/tri_edge_collapse.h>

#include "thermodec/common/errors.h"
#include "thermodec/decimation/global_ratio.h"

namespace thermodec {
namespace {

struct VVertex;
struct VFace;
struct VUsedTypes : vcg::UsedTypes<vcg::Use<VVertex>::AsVertexType, vcg::Use<VFace>::AsFaceType> {};
struct VVertex : vcg::Vertex<VUsedTypes, vcg::vertex::Coord3d, vcg::vertex::VFAdj, vcg::vertex::Mark,
                             vcg::vertex::BitFlags> {};
struct VFace : vcg::Face<VUsedTypes, vcg::face::VertexRef, vcg::face::VFAdj, vcg::face::BitFlags> {};
struct VMesh : vcg::tri::TriMesh<std::vector<VVertex>, std::vector<VFace>> {};

using VPair = vcg::tri::BasicVertexPair<VVertex>;
using Vec3 = Eigen::Vector3d;

enum VertexClass : uint8_t { kFree = 0, kContour = 1, kFrozen = 2 };

Vec3 to_eigen(const vcg::Point3d& p) { return Vec3(p[0], p[1], p[2]); }

// Everything the collapses share for one decimation call (vcg passes it as the parameter
// object, so no static state: concurrent calls are safe).
struct Context : vcg::BaseParameterClass {
  VMesh* m = nullptr;
  DecimationOptions opt;
  double cos_normal = 0.5;
  double cost_scale = 1.0;      // 1 / (bbox diagonal)^6: makes priorities scale-free floats
  double degenerate_area2 = 0;  // squared doubled-area below which a new face is degenerate
  int mark = 0;
  // Collapse counter and, per vertex, the counter value when its star last changed: an entry
  // evaluated after both its ends' stamps is still exact and need not be re-evaluated.
  int clock = 0;
  std::vector<int> stamp;

  std::vector<int> face_region, region_node, region_faces, face_component;
  std::vector<uint8_t> vclass;
  std::vector<int> node_faces, node_target;
  std::vector<int> node_free_removed;  // faces lost to exact contour collapses past the budget
  std::vector<double> node_area, node_area0;
  std::vector<double> comp_volume, comp_volume0;
  std::vector<char> comp_closed;
  std::vector<int> absorbed_by;  // removed face -> face that took over its area (provenance)
  std::vector<VFace*> star;      // scratch for evaluate()
  std::vector<VVertex*> scratch_v[3];
  std::vector<std::pair<VVertex*, VVertex*>> scratch_e[2];
  void* heap = nullptr;          // vcg's heap, for re-queuing re-evaluated collapses
  // vcg's stopping face count (sum of the targets); free removals lower it by what they took,
  // since they do not bring any node closer to its target.
  int* target_simplices = nullptr;

  int vi(const VVertex* v) const { return static_cast<int>(v - &m->vert[0]); }
  int fi(const VFace* f) const { return static_cast<int>(f - &m->face[0]); }
};

// Per-node / per-region / per-component bookkeeping of one candidate collapse. A collapse
// touches at most two regions (the removed vertex is free or on one contour), so four slots
// suffice; overflowing marks the candidate invalid rather than allocating per heap entry.
struct Delta {
  int key;
  double value;
};
struct Deltas {
  std::array<Delta, 4> d;
  int n = 0;
  bool overflow = false;
  void clear() { n = 0, overflow = false; }
  void add(int key, double value) {
    for (int i = 0; i < n; ++i)
      if (d[i].key == key) {
        d[i].value += value;
        return;
      }
    if (n == 4) {
      overflow = true;
      return;
    }
    d[n++] = {key, value};
  }
  const Delta* begin() const { return d.data(); }
  const Delta* end() const { return d.data() + n; }
  bool empty() const { return n == 0; }
};

// Lindstrom-Turk constraint accumulator: up to three orthonormal rows r_i with r_i . x = b_i.
struct Constraints {
  Eigen::Matrix3d r;
  Vec3 b;
  int n = 0;
  // LT's "alpha compatibility": a new constraint is kept only if it is not (nearly) a linear
  // combination of the ones already there (angle > 1 degree to their span).
  void add(Vec3 a, double rhs) {
    if (n == 3) return;
    const double norm0 = a.norm();
    if (!(norm0 > 0)) return;
    for (int i = 0; i < n; ++i) {
      const double c = a.dot(r.row(i));
      a -= c * r.row(i).transpose();
      rhs -= c * b[i];
    }
    const double norm = a.norm();
    constexpr double kSin1Deg = 0.0174524;
    if (norm <= kSin1Deg * norm0) return;
    r.row(n) = a / norm;
    b[n] = rhs / norm;
    ++n;
  }
  // Minimising x^T H x - 2 g^T x: its gradient rows H_i x = g_i become constraints in turn.
  void add_objective(const Eigen::Matrix3d& h, const Vec3& g) {
    for (int i = 0; i < 3 && n < 3; ++i) add(h.row(i).transpose(), g[i]);
  }
  Vec3 solve() const { return r.transpose() * b; }  // n == 3: r is orthonormal
};

class NodeCollapse : public vcg::tri::TriEdgeCollapse<VMesh, VPair, NodeCollapse> {
  using Base = vcg::tri::TriEdgeCollapse<VMesh, VPair, NodeCollapse>;

 public:
  using HeapType = Base::HeapType;
  using HeapElem = Base::HeapElem;

  NodeCollapse(const VPair& p, int mark, vcg::BaseParameterClass* pp) {
    localMark = mark;
    pos = p;
    _priority = ComputePriority(pp);
  }

  bool valid() const { return valid_; }

  ScalarType ComputePriority(vcg::BaseParameterClass* pp) override {
    auto& c = *static_cast<Context*>(pp);
    valid_ = false;
    _priority = std::numeric_limits<float>::max();
    VVertex* a = pos.V(0);
    VVertex* b = pos.V(1);
    evaluated_at_ = c.clock;
    // A collapse removes the faces on its edge. If none of their nodes has budget left it can
    // never run (budgets only shrink), so do not even queue it; nor if one has none and free
    // exact-contour removals are off. Otherwise evaluate() decides exactness per node.
    {
      int spent = 0, with_budget = 0;
      for (vcg::face::VFIterator<VFace> it(a); !it.End(); ++it)
        if (it.V1() == b || it.V2() == b) {
          const int node = c.region_node[c.face_region[c.fi(it.F())]];
          ++(c.node_faces[node] <= c.node_target[node] ? spent : with_budget);
        }
      if (with_budget == 0 || (spent > 0 && !c.opt.free_exact_contour_collapses)) return _priority;
    }
    const uint8_t ca = c.vclass[c.vi(a)], cb = c.vclass[c.vi(b)];
    if (ca == kFree && cb == kFree) {
      evaluate(c, a, b, /*optimal=*/true);
    } else if (ca == kFree) {
      evaluate(c, a, b, false);
    } else if (cb == kFree) {
      evaluate(c, b, a, false);
    } else {
      // Both ends constrained: only along a contour edge, never between two frozen vertices.
      if (ca == kFrozen && cb == kFrozen) return _priority;
      if (!is_contour_edge(c, a, b)) return _priority;
      if (ca == kContour && cb == kContour) {
        evaluate(c, a, b, false);
        if (c.vclass[c.vi(b)] == kContour) {
          NodeCollapse other = *this;
          other.evaluate(c, b, a, false);
          if (other.valid_ && (!valid_ || other._priority < _priority)) *this = other;
        }
      } else if (ca == kContour) {
        evaluate(c, a, b, false);
      } else {
        evaluate(c, b, a, false);
      }
    }
    return _priority;
  }

  bool IsUpToDate() const override {
    const VVertex* v0 = pos.cV(0);
    const VVertex* v1 = pos.cV(1);
    return !v0->IsD() && !v1->IsD() && localMark >= v0->cIMark() && localMark >= v1->cIMark();
  }

  bool IsFeasible(vcg::BaseParameterClass* pp) override {
    auto& c = *static_cast<Context*>(pp);
    // Lazy re-evaluation: after a collapse only the edges at the kept vertex are re-queued;
    // other entries whose stars changed are re-evaluated here when they surface. If the cost
    // rose, the collapse goes back into the heap at its new priority instead of running now.
    const ScalarType stored = _priority;
    const bool fresh = c.stamp[c.vi(pos.V(0))] <= evaluated_at_ && c.stamp[c.vi(pos.V(1))] <= evaluated_at_;
    if (!fresh) ComputePriority(pp);
    if (!valid_) return false;
    if (_priority > stored) {
      auto& heap = *static_cast<HeapType*>(c.heap);
      heap.push_back(HeapElem(new NodeCollapse(*this)));
      std::push_heap(heap.begin(), heap.end());
      return false;
    }
    // Budgets: each node pays for its removed faces, except one whose geometry the collapse
    // leaves unchanged (exact_per_node_); somebody must pay, or the collapse serves no one.
    bool paid = false;
    for (const auto& d : removed_per_node_) {
      if (c.node_faces[d.key] - static_cast<int>(d.value) >= c.node_target[d.key])
        paid = true;
      else if (!is_exact_for(d.key) || c.node_faces[d.key] - static_cast<int>(d.value) < c.opt.min_faces_per_node)
        return false;
    }
    if (!paid) return false;
    for (const auto& d : removed_per_region_)
      if (c.region_faces[d.key] - static_cast<int>(d.value) < 1) return false;
    for (const auto& d : area_delta_) {
      const double after = c.node_area[d.key] + d.value;
      if (std::abs(after - c.node_area0[d.key]) > c.opt.max_relative_area_change * c.node_area0[d.key])
        return false;
    }
    for (const auto& d : volume_delta_) {
      if (!c.comp_closed[d.key]) continue;
      const double after = c.comp_volume[d.key] + d.value;
      if (std::abs(after - c.comp_volume0[d.key]) >
          c.opt.max_relative_volume_change * std::abs(c.comp_volume0[d.key]))
        return false;
    }
    return link_condition(c);
  }

  void Execute(VMesh& m, vcg::BaseParameterClass* pp) override {
    auto& c = *static_cast<Context*>(pp);
    // vcg keeps V(1) and deletes V(0); UpdateHeap relies on the same convention.
    VVertex* gone = pos.V(0);
    VVertex* kept = pos.V(1);
    std::vector<int> removed_faces;
    for (vcg::face::VFIterator<VFace> it(gone); !it.End(); ++it)
      if (it.V1() == kept || it.V2() == kept) removed_faces.push_back(c.fi(it.F()));
    for (const auto& d : removed_per_node_) {
      const int k = static_cast<int>(d.value);
      if (c.node_faces[d.key] - k < c.node_target[d.key]) {
        c.node_free_removed[d.key] += k;
        if (c.target_simplices != nullptr) *c.target_simplices -= k;
      }
      c.node_faces[d.key] -= k;
    }
    for (const auto& d : removed_per_region_) c.region_faces[d.key] -= static_cast<int>(d.value);
    for (const auto& d : area_delta_) c.node_area[d.key] += d.value;
    for (const auto& d : volume_delta_) c.comp_volume[d.key] += d.value;
    vcg::tri::EdgeCollapser<VMesh, VPair>::Do(m, pos, vcg::Point3d(x_[0], x_[1], x_[2]));
    // Provenance: hand each removed face to a surviving face around the kept vertex, same
    // region first (it covers the same node surface), else same node, else any.
    for (int f : removed_faces) {
      int best = -1, best_rank = 3;
      for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it) {
        const int g = c.fi(it.F());
        const int rank = c.face_region[g] == c.face_region[f]                           ? 0
                         : c.region_node[c.face_region[g]] == c.region_node[c.face_region[f]] ? 1
                                                                                          : 2;
        if (rank < best_rank) best = g, best_rank = rank;
      }
      c.absorbed_by[f] = best;
    }
  }

  void UpdateHeap(HeapType& heap, vcg::BaseParameterClass* pp) override {
    auto& c = *static_cast<Context*>(pp);
    ++c.mark;
    VVertex* kept = pos.V(1);
    kept->IMark() = c.mark;  // invalidates the old entries at the kept vertex
    auto& ring = c.scratch_v[0];
    ring.clear();
    for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it) {
      ring.push_back(it.V1());
      ring.push_back(it.V2());
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    ++c.clock;
    c.stamp[c.vi(kept)] = c.clock;
    for (VVertex* r : ring) c.stamp[c.vi(r)] = c.clock;
    for (VVertex* r : ring) push(heap, std::min(kept, r), std::max(kept, r), c);
  }

  static void push(HeapType& heap, VVertex* a, VVertex* b, Context& c) {
    auto* op = new NodeCollapse(VPair(a, b), c.mark, &c);
    if (!op->valid()) {
      delete op;
      return;
    }
    heap.push_back(HeapElem(op));
    std::push_heap(heap.begin(), heap.end());
  }

  static void Init(VMesh& m, HeapType& heap, vcg::BaseParameterClass* pp) {
    auto& c = *static_cast<Context*>(pp);
    heap.clear();
    std::vector<std::pair<VVertex*, VVertex*>> edges;
    for (auto& f : m.face)
      for (int j = 0; j < 3; ++j)
        edges.emplace_back(std::min(f.V0(j), f.V1(j)), std::max(f.V0(j), f.V1(j)));
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& e : edges) {
      auto* op = new NodeCollapse(VPair(e.first, e.second), c.mark, &c);
      if (op->valid())
        heap.push_back(HeapElem(op));
      else
        delete op;
    }
  }
  static void Finalize(VMesh&, HeapType&, vcg::BaseParameterClass*) {}
  static float HeapSimplexRatio(vcg::BaseParameterClass*) { return 8.0f; }

 private:
  bool is_exact_for(int node) const {
    for (const auto& d : exact_per_node_)
      if (d.key == node) return d.value > 0;
    return false;
  }

  // Does the edge (a, b) separate two regions, or bound the surface (1 face or > 2 faces)?
  static bool is_contour_edge(const Context& c, VVertex* a, VVertex* b) {
    int count = 0, region0 = -1;
    bool differ = false;
    for (vcg::face::VFIterator<VFace> it(a); !it.End(); ++it) {
      if (it.V1() != b && it.V2() != b) continue;
      const int r = c.face_region[c.fi(it.F())];
      if (count == 0)
        region0 = r;
      else if (r != region0)
        differ = true;
      ++count;
    }
    return count != 2 || differ;
  }

  // The other contour neighbour of contour vertex v (not `not_this`), or nullptr.
  static VVertex* other_contour_neighbour(const Context& c, VVertex* v, VVertex* not_this) {
    std::array<VVertex*, 16> seen{};
    int n = 0;
    for (vcg::face::VFIterator<VFace> it(v); !it.End(); ++it)
      for (VVertex* w : {it.V1(), it.V2()}) {
        if (w == not_this || std::find(seen.begin(), seen.begin() + n, w) != seen.begin() + n) continue;
        if (n < 16) seen[n++] = w;
        if (is_contour_edge(c, v, w)) return w;
      }
    return nullptr;
  }

  // Corners `q` of star face f once this collapse puts its vertex at x, the index `moved_at` of
  // a corner that moved; returns how many moved (2: f is on the collapsed edge and disappears).
  int corners_after(const VFace* f, const Vec3& x, std::array<Vec3, 3>& q, int& moved_at) const {
    int moved = 0;
    for (int k = 0; k < 3; ++k) {
      q[k] = to_eigen(f->cP(k));
      if (f->cV(k) == pos.cV(0) || f->cV(k) == pos.cV(1)) q[k] = x, moved_at = k, ++moved;
    }
    return moved;
  }

  // Area-neutral placement of a collapse inside one region (both ends free): moves the
  // Lindstrom-Turk point x_ along the gradient of the star's area until the node's area is
  // back at its input value, or at least the star's own area is unchanged.
  //
  // Why: a node that keeps its heat input radiates it from its area, so a relative area change
  // dA/A moves it by dT = -T dA/(4A) (0.1 % is ~0.07 K at 280 K) whatever its view factors do.
  // On curved parts (CAD cylinders, the dish) every volume-preserving collapse grows the area
  // a little, and the per-node bound then stops the decimation early. Volume matters little
  // thermally (the bound on closed volumes still holds: IsFeasible). The area's gradient is
  // normal to the surface on a curved star and vanishes on a flat one, where the area is
  // preserved anyway; a correction that would move x_ by more than a tenth of the star's edge
  // length is not made (a flat star cannot pay back another collapse's drift without a tent).
  void place_area_neutral(const Context& c) {
    const auto& star = c.star;
    double area_before = 0;
    for (const VFace* f : star) {
      const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
      area_before += 0.5 * (p1 - p0).cross(p2 - p0).norm();
    }
    if (!(area_before > 0)) return;
    // Area of the surviving star faces with the moved vertex at x [m^2], and its gradient [m]:
    // for a triangle (x, b, c), d area / dx = (b - c) x n / 2 with n its unit normal.
    auto area_at = [&](const Vec3& x, Vec3& grad) {
      double area = 0;
      grad.setZero();
      std::array<Vec3, 3> q;
      for (const VFace* f : star) {
        int j = -1;
        if (corners_after(f, x, q, j) != 1) continue;  // the faces on the collapsed edge disappear
        const Vec3& b = q[(j + 1) % 3];
        const Vec3& d = q[(j + 2) % 3];
        const Vec3 n = (b - x).cross(d - x);
        const double len = n.norm();
        area += 0.5 * len;
        if (len > 0) grad += 0.5 * (b - d).cross(n / len);
      }
      return area;
    };
    const double max_move = 0.1 * std::sqrt(2.0 * area_before / static_cast<double>(star.size()));
    const int node = c.region_node[c.face_region[c.fi(star.front())]];
    const double drift = c.node_area[node] - c.node_area0[node];
    const double targets[2] = {area_before - drift, area_before};  // the second if the first fails
    for (int k = 0; k < (drift != 0.0 ? 2 : 1); ++k) {
      const double target = targets[k];
      Vec3 x = x_, grad;
      bool converged = false;
      for (int it = 0; it < 6 && !converged; ++it) {
        const double residual = target - area_at(x, grad);
        converged = std::abs(residual) <= 1e-12 * area_before;
        const double g2 = grad.squaredNorm();
        if (converged || !(g2 > 0)) break;
        x += (residual / g2) * grad;
        if (!((x - x_).norm() <= max_move)) break;
      }
      if (converged && (x - x_).norm() <= max_move && keeps_closed_volume(c, x)) {
        x_ = x;
        return;
      }
    }
  }

  // True if collapsing into x keeps the star's closed part within max_relative_volume_change.
  // The LT point x_ keeps the volume; an area-neutral point spends the volume budget, and a
  // collapse refused for volume is lost, so the LT point is kept instead. (Measured on Juno and
  // NPP_16: falling back reaches further than refusing, and than cutting the move short where
  // the volume budget ends.)
  bool keeps_closed_volume(const Context& c, const Vec3& x) const {
    const int comp = c.face_component[c.fi(c.star.front())];
    if (!c.comp_closed[comp]) return true;
    double delta = 0;  // change of the closed part's volume [m^3]
    std::array<Vec3, 3> q;
    for (const VFace* f : c.star) {
      int j = -1;
      const int moved = corners_after(f, x, q, j);
      const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
      delta -= p0.dot(p1.cross(p2)) / 6.0;
      if (moved == 1) delta += q[0].dot(q[1].cross(q[2])) / 6.0;
    }
    return std::abs(c.comp_volume[comp] + delta - c.comp_volume0[comp]) <=
           c.opt.max_relative_volume_change * std::abs(c.comp_volume0[comp]);
  }

  // Evaluates removing `gone` into `kept` (kept moves too when `optimal`): placement, validity,
  // cost and the bookkeeping deltas used by IsFeasible/Execute.
  void evaluate(Context& c, VVertex* gone, VVertex* kept, bool optimal) {
    valid_ = false;
    _priority = std::numeric_limits<float>::max();
    pos.V(0) = gone;
    pos.V(1) = kept;
    removed_per_node_.clear();
    removed_per_region_.clear();
    area_delta_.clear();
    volume_delta_.clear();
    exact_per_node_.clear();

    const Vec3 pg = to_eigen(gone->cP()), pk = to_eigen(kept->cP());

    // Faces of the two stars (the removed ones are in both; list them once).
    auto& star_ = c.star;
    star_.clear();
    for (vcg::face::VFIterator<VFace> it(gone); !it.End(); ++it) star_.push_back(it.F());
    for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it)
      if (it.V1() != gone && it.V2() != gone) star_.push_back(it.F());

    double boundary_cost = 0;
    bool straight = false;  // gone lies on a straight contour (free_exact_contour_collapses)
    if (optimal) {
      // Lindstrom-Turk placement: volume preservation, then volume optimisation, then shape.
      Constraints k;
      Vec3 nsum = Vec3::Zero();
      double dsum = 0;
      Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
      Vec3 g = Vec3::Zero();
      for (VFace* f : star_) {
        const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
        const Vec3 n = (p1 - p0).cross(p2 - p0);
        const double d = n.dot(p0);
        nsum += n;
        dsum += d;
        h += n * n.transpose();
        g += n * d;
      }
      k.add(nsum, dsum);
      k.add_objective(h, g);
      Vec3 centroid = Vec3::Zero();
      int nlink = 0;
      for (VFace* f : star_)
        for (int j = 0; j < 3; ++j) {
          VVertex* v = f->V(j);
          if (v == gone || v == kept) continue;
          centroid += to_eigen(v->cP());
          ++nlink;
        }
      // Shape optimisation: sum |x - p_j|^2 over link vertices -> H = nlink I, g = sum p_j.
      if (nlink > 0) k.add_objective(Eigen::Matrix3d::Identity() * nlink, centroid);
      x_ = k.n == 3 ? k.solve() : 0.5 * (pg + pk);
      if (!x_.allFinite()) return;
      if (c.opt.area_neutral_placement) place_area_neutral(c);
    } else {
      x_ = pk;
      if (c.vclass[c.vi(gone)] == kContour) {
        // The contour loses `gone`; it must stay nearly straight there (shape error bound).
        VVertex* w = other_contour_neighbour(c, gone, kept);
        if (w == nullptr || w == kept) return;
        const Vec3 pw = to_eigen(w->cP());
        const Vec3 seg = pw - pk;
        const double len2 = seg.squaredNorm();
        if (!(len2 > 0)) return;
        const double t = std::clamp((pg - pk).dot(seg) / len2, 0.0, 1.0);
        const double dev = (pg - (pk + t * seg)).norm();
        if (dev > c.opt.max_contour_deviation * std::sqrt(len2)) return;
        straight = c.opt.free_exact_contour_collapses && dev <= c.opt.exact_contour_tolerance * std::sqrt(len2);
        // LT boundary preservation: squared swept area of the contour, times a length^2.
        const double swept = 0.5 * (pg - pk).cross(pw - pk).norm();
        boundary_cost = swept * swept * len2;
      }
    }

    // Validity (no flips, no degenerate faces) and cost. On a straight contour, also whether
    // each node's faces around `gone` are coplanar and keep their total area: then moving
    // `gone` onto `kept` (in the same plane, on the same line) re-triangulates the same
    // polygon and that node's geometry is unchanged.
    struct NodePlane {
      int node;
      Vec3 normal;
      bool coplanar;
      double area_before, area_after;
    };
    std::array<NodePlane, 4> planes;
    int nplanes = 0;
    auto plane_of = [&](int node, const Vec3& n0) -> NodePlane* {
      for (int i = 0; i < nplanes; ++i)
        if (planes[i].node == node) return &planes[i];
      if (nplanes == 4) return nullptr;
      const double len = n0.norm();
      planes[nplanes] = {node, len > 0 ? Vec3(n0 / len) : Vec3::Zero(), len > 0, 0.0, 0.0};
      return &planes[nplanes++];
    };
    double vol_cost = 0, vol_change = 0, shape = 0, mean_area2 = 0;
    for (VFace* f : star_) {
      const int fidx = c.fi(f);
      const int region = c.face_region[fidx], node = c.region_node[region];
      std::array<Vec3, 3> p, q;
      bool has_gone = false, has_kept = false;
      for (int j = 0; j < 3; ++j) {
        p[j] = to_eigen(f->cP(j));
        q[j] = p[j];
        if (f->cV(j) == gone) q[j] = x_, has_gone = true;
        if (f->cV(j) == kept) {
          has_kept = true;
          if (optimal) q[j] = x_;
        }
      }
      const Vec3 n0 = (p[1] - p[0]).cross(p[2] - p[0]);
      const double a0 = 0.5 * n0.norm();
      mean_area2 += a0;
      NodePlane* plane = nullptr;
      if (straight && has_gone) {
        plane = plane_of(node, n0);
        if (plane == nullptr) {
          straight = false;
        } else {
          const double len = n0.norm();
          if (!(len > 0) || (n0 / len - plane->normal).norm() > c.opt.exact_contour_tolerance) plane->coplanar = false;
          plane->area_before += a0;
        }
      }
      // LT volume terms: tetrahedron between the new vertex and the old face.
      const double tet = n0.dot(x_ - p[0]) / 6.0;
      vol_cost += tet * tet;
      vol_change += tet;
      if (has_gone && has_kept) {  // this face disappears
        removed_per_node_.add(node, 1.0);
        removed_per_region_.add(region, 1.0);
        area_delta_.add(node, -a0);
        volume_delta_.add(c.face_component[fidx], -p[0].dot(p[1].cross(p[2])) / 6.0);
        continue;
      }
      const Vec3 n1 = (q[1] - q[0]).cross(q[2] - q[0]);
      const double n1sq = n1.squaredNorm();
      if (n1sq <= c.degenerate_area2) return;
      if (n0.dot(n1) < c.cos_normal * std::sqrt(n0.squaredNorm() * n1sq)) return;
      area_delta_.add(node, 0.5 * std::sqrt(n1sq) - a0);
      if (plane != nullptr) plane->area_after += 0.5 * std::sqrt(n1sq);
      volume_delta_.add(c.face_component[fidx],
                (q[0].dot(q[1].cross(q[2])) - p[0].dot(p[1].cross(p[2]))) / 6.0);
      for (int j = 0; j < 3; ++j)
        if (f->cV(j) != gone && f->cV(j) != kept) shape += (q[j] - x_).squaredNorm();
    }
    if (removed_per_node_.empty()) return;  // not an edge of a face (cannot happen) -> skip
    if (removed_per_node_.overflow || removed_per_region_.overflow || area_delta_.overflow ||
        volume_delta_.overflow)
      return;
    if (straight)
      for (int i = 0; i < nplanes; ++i) {
        const NodePlane& p = planes[i];
        const bool exact = p.coplanar && std::abs(p.area_after - p.area_before) <=
                                             c.opt.exact_contour_tolerance * p.area_before;
        exact_per_node_.add(p.node, exact ? 1.0 : 0.0);
      }
    mean_area2 /= static_cast<double>(star_.size());
    mean_area2 *= mean_area2;
    const double cost = vol_cost + vol_change * vol_change + boundary_cost +
                        c.opt.shape_weight * shape * mean_area2;
    _priority = static_cast<ScalarType>(cost * c.cost_scale);
    valid_ = std::isfinite(_priority);
  }

  // Link condition Lk(a) n Lk(b) == Lk(ab), written with sorted vectors (no maps) and valid
  // when the kept vertex is non-manifold (frozen): the removed vertex is always manifold.
  bool link_condition(Context& c) const {
    VVertex* gone = pos.cV(0);
    VVertex* kept = pos.cV(1);
    auto& lg = c.scratch_v[0];
    auto& lk = c.scratch_v[1];
    auto& opposite = c.scratch_v[2];
    auto& eg = c.scratch_e[0];
    auto& ek = c.scratch_e[1];
    lg.clear(), lk.clear(), opposite.clear(), eg.clear(), ek.clear();
    auto edge = [](VVertex* x, VVertex* y) { return std::make_pair(std::min(x, y), std::max(x, y)); };
    for (vcg::face::VFIterator<VFace> it(gone); !it.End(); ++it) {
      VVertex* v1 = it.V1();
      VVertex* v2 = it.V2();
      if (v1 == kept)
        opposite.push_back(v2);
      else if (v2 == kept)
        opposite.push_back(v1);
      else
        eg.push_back(edge(v1, v2));
      lg.push_back(v1);
      lg.push_back(v2);
    }
    for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it) {
      VVertex* v1 = it.V1();
      VVertex* v2 = it.V2();
      if (v1 != gone && v2 != gone) ek.push_back(edge(v1, v2));
      lk.push_back(v1);
      lk.push_back(v2);
    }
    if (opposite.empty() || opposite.size() > 2) return false;
    for (auto* v : {&lg, &lk, &opposite}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    // Shared link vertices (other than the edge's own ends) must be exactly the opposite ones.
    size_t shared = 0;
    for (size_t i = 0, j = 0; i < lg.size() && j < lk.size();) {
      if (lg[i] == lk[j]) {
        if (lg[i] != gone && lg[i] != kept) {
          if (!std::binary_search(opposite.begin(), opposite.end(), lg[i])) return false;
          ++shared;
        }
        ++i, ++j;
      } else if (lg[i] < lk[j]) {
        ++i;
      } else {
        ++j;
      }
    }
    if (shared != opposite.size()) return false;
    // No edge may be in both links (e.g. a tetrahedron fold), else faces would duplicate.
    std::sort(eg.begin(), eg.end());
    std::sort(ek.begin(), ek.end());
    for (size_t i = 0, j = 0; i < eg.size() && j < ek.size();) {
      if (eg[i] == ek[j]) return false;
      if (eg[i] < ek[j])
        ++i;
      else
        ++j;
    }
    return true;
  }

  bool valid_ = false;
  int evaluated_at_ = 0;
  Vec3 x_ = Vec3::Zero();
  Deltas removed_per_node_, removed_per_region_, area_delta_, volume_delta_;
  Deltas exact_per_node_;  // node -> 1 if this collapse leaves its geometry unchanged
};

void check_input(const Mesh& mesh) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (mesh.V.cols() != 3 && nv > 0) throw InvalidInput("decimate: V must be #V x 3");
  if (mesh.F.cols() != 3 && nf > 0) throw InvalidInput("decimate: F must be #F x 3");
  if (mesh.face_node.size() != nf)
    throw InvalidInput("decimate: face_node has " + std::to_string(mesh.face_node.size()) +
                       " entries for " + std::to_string(nf) + " faces");
  for (int f = 0; f < nf; ++f) {
    for (int j = 0; j < 3; ++j)
      if (mesh.F(f, j) < 0 || mesh.F(f, j) >= nv)
        throw InvalidInput("decimate: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(mesh.F(f, j)) + " outside [0, " + std::to_string(nv) + ")");
    if (mesh.face_node[f] < -1)
      throw InvalidInput("decimate: face " + std::to_string(f) + " has node " +
                         std::to_string(mesh.face_node[f]));
  }
  if (!mesh.V.allFinite()) throw InvalidInput("decimate: vertex coordinates contain NaN or inf");
}

int attr(const Eigen::VectorXi& a, int f) { return a.size() > f ? a[f] : -1; }

}  // namespace

DecimationResult decimate_nodes(const Mesh& mesh, const Eigen::VectorXd& target_ratio_per_node,
                                const DecimationOptions& options) {
  check_input(mesh);
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  int num_nodes = static_cast<int>(mesh.node_names.size());
  bool has_unassigned = false;
  for (int f = 0; f < nf; ++f) {
    num_nodes = std::max(num_nodes, mesh.face_node[f] + 1);
    has_unassigned |= mesh.face_node[f] < 0;
  }
  if (target_ratio_per_node.size() < num_nodes)
    throw InvalidInput("decimate: " + std::to_string(target_ratio_per_node.size()) +
                       " node ratios for " + std::to_string(num_nodes) + " nodes");
  for (int i = 0; i < target_ratio_per_node.size(); ++i)
    if (!(target_ratio_per_node[i] >= 0 && target_ratio_per_node[i] <= 1))
      throw InvalidInput("decimate: ratio of node " + std::to_string(i) + " is " +
                         std::to_string(target_ratio_per_node[i]) + ", expected in [0, 1]");
  if (!(options.unassigned_ratio >= 0 && options.unassigned_ratio <= 1))
    throw InvalidInput("decimate: unassigned_ratio must be in [0, 1]");
  if (!(options.max_relative_area_change >= 0) || !(options.max_relative_volume_change >= 0) ||
      !(options.max_contour_deviation >= 0) || !(options.exact_contour_tolerance >= 0) ||
      options.min_faces_per_node < 1)
    throw InvalidInput("decimate: tolerances must be >= 0 and min_faces_per_node >= 1");

  const int groups = num_nodes + (has_unassigned ? 1 : 0);
  auto group_of = [&](int f) { return mesh.face_node[f] >= 0 ? mesh.face_node[f] : num_nodes; };

  Context c;
  c.opt = options;
  c.cos_normal = std::cos(options.max_normal_deviation_deg * M_PI / 180.0);

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
  // Non-manifold vertices: the faces around a vertex must form one fan (connected through
  // edges at that vertex with exactly two faces).
  {
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
  for (int f = 0; f < nf; ++f) {
    if (face_on_open_edge[f]) c.comp_closed[c.face_component[f]] = 0;
    const Vec3 p0 = mesh.V.row(mesh.F(f, 0)), p1 = mesh.V.row(mesh.F(f, 1)), p2 = mesh.V.row(mesh.F(f, 2));
    c.comp_volume0[c.face_component[f]] += p0.dot(p1.cross(p2)) / 6.0;
  }
  c.comp_volume = c.comp_volume0;

  // Node face counts, targets and areas.
  c.node_faces.assign(groups, 0);
  c.node_area0.assign(groups, 0.0);
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = mesh.V.row(mesh.F(f, 0)), p1 = mesh.V.row(mesh.F(f, 1)), p2 = mesh.V.row(mesh.F(f, 2));
    ++c.node_faces[group_of(f)];
    c.node_area0[group_of(f)] += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  c.node_area = c.node_area0;
  c.node_free_removed.assign(groups, 0);
  c.node_target.resize(groups);
  int total_target = 0;
  for (int g = 0; g < groups; ++g) {
    const double ratio = g < num_nodes ? target_ratio_per_node[g] : options.unassigned_ratio;
    const int keep = static_cast<int>(std::lround(c.node_faces[g] * (1.0 - ratio)));
    c.node_target[g] = std::min(c.node_faces[g], std::max(keep, options.min_faces_per_node));
    total_target += c.node_target[g];
  }

  // Scale: priorities are floats in vcg's heap, so make the cost dimensionless.
  double diag = 1.0;
  if (nv > 0) diag = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  if (!(diag > 0)) diag = 1.0;
  c.cost_scale = 1.0 / std::pow(diag, 6);
  c.degenerate_area2 = std::pow(1e-12 * diag * diag, 2);

  // Build the vcg mesh; vertex/face indices equal the input ones (vcg only flags deletions).
  VMesh m;
  c.m = &m;
  vcg::tri::Allocator<VMesh>::AddVertices(m, nv);
  vcg::tri::Allocator<VMesh>::AddFaces(m, nf);
  for (int v = 0; v < nv; ++v) m.vert[v].P() = vcg::Point3d(mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) m.face[f].V(j) = &m.vert[mesh.F(f, j)];
  vcg::tri::UpdateTopology<VMesh>::VertexFace(m);
  c.absorbed_by.assign(nf, -1);
  c.stamp.assign(nv, 0);

  int collapses = 0;
  bool needs_work = false;
  for (int g = 0; g < groups; ++g) needs_work |= c.node_target[g] < c.node_faces[g];
  if (needs_work && nf > 0) {
    vcg::LocalOptimization<VMesh> opt(m, &c);
    c.heap = &opt.h;
    opt.Init<NodeCollapse>();
    opt.SetTargetSimplices(total_target);
    c.target_simplices = &opt.nTargetSimplices;
    opt.DoOptimization();
    collapses = opt.nPerformedOps;
  }

  // Assemble the result.
  DecimationResult res;
  res.collapses = collapses;
  std::vector<int> new_vertex(nv, -1);
  std::vector<int> kept_faces;
  for (int f = 0; f < nf; ++f)
    if (!m.face[f].IsD()) kept_faces.push_back(f);
  for (int f : kept_faces)
    for (int j = 0; j < 3; ++j) new_vertex[c.vi(m.face[f].V(j))] = 1;
  int nv_out = 0;  // surviving vertices keep their input order
  for (int& nvx : new_vertex) nvx = nvx > 0 ? nv_out++ : -1;
  Mesh& out = res.mesh;
  out.V.resize(nv_out, 3);
  res.fine_vertex_of_coarse.resize(nv_out);
  for (int v = 0; v < nv; ++v)
    if (new_vertex[v] >= 0) {
      for (int k = 0; k < 3; ++k) out.V(new_vertex[v], k) = m.vert[v].cP()[k];
      res.fine_vertex_of_coarse[new_vertex[v]] = v;
    }
  const int nf_out = static_cast<int>(kept_faces.size());
  out.F.resize(nf_out, 3);
  out.face_node.resize(nf_out);
  out.face_material.resize(nf_out);
  out.face_back_material.resize(nf_out);
  res.fine_face_of_coarse.resize(nf_out);
  std::vector<int> coarse_of(nf, -1);
  for (int i = 0; i < nf_out; ++i) {
    const int f = kept_faces[i];
    for (int j = 0; j < 3; ++j) out.F(i, j) = new_vertex[c.vi(m.face[f].V(j))];
    out.face_node[i] = mesh.face_node[f];
    out.face_material[i] = attr(mesh.face_material, f);
    out.face_back_material[i] = attr(mesh.face_back_material, f);
    res.fine_face_of_coarse[i] = f;
    coarse_of[f] = i;
  }
  out.node_names = mesh.node_names;
  out.material_names = mesh.material_names;
  res.coarse_face_of_fine.resize(nf);
  for (int f = 0; f < nf; ++f) {
    int g = f;
    while (coarse_of[g] < 0 && c.absorbed_by[g] >= 0) g = c.absorbed_by[g];
    res.coarse_face_of_fine[f] = coarse_of[g];
  }

  res.nodes.resize(groups);
  for (int g = 0; g < groups; ++g) {
    res.nodes[g].area_before_m2 = c.node_area0[g];
    res.nodes[g].target_faces = c.node_target[g];
    res.nodes[g].faces_removed_free = c.node_free_removed[g];
  }
  for (int f = 0; f < nf; ++f) ++res.nodes[group_of(f)].faces_before;
  for (int i = 0; i < nf_out; ++i) {
    const int f = kept_faces[i];
    const Vec3 p0 = out.V.row(out.F(i, 0)), p1 = out.V.row(out.F(i, 1)), p2 = out.V.row(out.F(i, 2));
    auto& s = res.nodes[group_of(f)];
    ++s.faces_after;
    s.area_after_m2 += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  for (auto& s : res.nodes) s.reached = s.faces_after <= s.target_faces;
  std::vector<double> volume_after(ncomp, 0.0);
  for (int i = 0; i < nf_out; ++i) {
    const Vec3 p0 = out.V.row(out.F(i, 0)), p1 = out.V.row(out.F(i, 1)), p2 = out.V.row(out.F(i, 2));
    volume_after[c.face_component[kept_faces[i]]] += p0.dot(p1.cross(p2)) / 6.0;
  }
  for (int k = 0; k < ncomp; ++k)
    if (c.comp_closed[k]) {
      res.closed_volume_before_m3.push_back(c.comp_volume0[k]);
      res.closed_volume_after_m3.push_back(volume_after[k]);
    }
  return res;
}

DecimationResult decimate_to_global_ratio(const Mesh& mesh, double global_ratio,
                                          const DecimationOptions& options, int max_rounds) {
  if (!(global_ratio >= 0 && global_ratio < 1))
    throw InvalidInput("decimate: global ratio " + std::to_string(global_ratio) + " not in [0, 1)");
  int num_nodes = static_cast<int>(mesh.node_names.size());
  bool has_unassigned = false;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    num_nodes = std::max(num_nodes, mesh.face_node[f] + 1);
    has_unassigned |= mesh.face_node[f] < 0;
  }
  const int groups = num_nodes + (has_unassigned ? 1 : 0);
  Eigen::VectorXi counts = Eigen::VectorXi::Zero(groups);
  for (int f = 0; f < mesh.num_faces(); ++f)
    ++counts[mesh.face_node[f] >= 0 ? mesh.face_node[f] : num_nodes];
  Eigen::VectorXd cap = Eigen::VectorXd::Ones(groups);
  Eigen::VectorXd ratios = node_ratios_for_global_ratio(counts, global_ratio, options.min_faces_per_node, cap);
  DecimationResult res;
  for (int round = 0; round < std::max(1, max_rounds); ++round) {
    DecimationOptions o = options;
    if (has_unassigned) o.unassigned_ratio = ratios[num_nodes];
    res = decimate_nodes(mesh, ratios.head(num_nodes), o);
    // A node stopped short by the constraints caps its ratio at what it reached; the rule then
    // hands its deficit to the next nodes.
    // Each node stops within one collapse (<= 2 faces) of its rounded target, so a total within
    // `groups` faces of the global target is met; rerunning for that would only cost time.
    const int global_target = static_cast<int>(std::lround((1.0 - global_ratio) * mesh.num_faces()));
    if (res.mesh.num_faces() <= global_target + groups) break;
    bool short_of_target = false;
    for (int g = 0; g < groups; ++g)
      if (!res.nodes[g].reached && counts[g] > 0) {
        short_of_target = true;
        cap[g] = 1.0 - static_cast<double>(res.nodes[g].faces_after) / counts[g];
      }
    if (!short_of_target) break;
    const Eigen::VectorXd next = node_ratios_for_global_ratio(counts, global_ratio, options.min_faces_per_node, cap);
    if ((next - ratios).cwiseAbs().maxCoeff() < 1e-12) break;
    ratios = next;
  }
  return res;
}

}  // namespace thermodec
