#pragma once
// Private to core/src/decimation: the vcglib mesh the collapses run on and the state they
// share for one decimate_nodes() call (Context), with the small accumulators of one candidate
// collapse (Deltas, Lindstrom-Turk Constraints).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/local_optimization.h>
#include <vcg/complex/algorithms/local_optimization/tri_edge_collapse.h>

#include "thermodec/decimation/decimate_nodes.h"

namespace thermodec::collapse {

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

inline Vec3 to_eigen(const vcg::Point3d& p) { return Vec3(p[0], p[1], p[2]); }

//! One face around a candidate collapse, before and after it (collapse_cost.h).
struct StarFaceChange {
  std::array<Vec3, 3> before, after;  //!< corners [m]; `after` unused when removed
  int node = 0;                       //!< the face's node group
  bool removed = false;               //!< the face disappears with the collapse
  double swept_m3 = 0;                //!< signed volume the face sweeps (LT volume terms)
};

//! What a candidate collapse does to its star, as its cost sees it (collapse_cost.h).
struct StarChange {
  std::vector<StarFaceChange> faces;  //!< in star order (the cost's sums follow it)
  double star_area_m2 = 0;            //!< summed input area of the star's faces (shape term scale)
  int star_faces = 0;                 //!< faces in the star (shape term scale)
  double boundary_m6 = 0;             //!< LT boundary term of a contour collapse
  double shape_m2 = 0;                //!< sum |q - x|^2 over the link corners of surviving faces
  void clear() {
    faces.clear();
    star_area_m2 = 0, star_faces = 0, boundary_m6 = 0, shape_m2 = 0;
  }
};

// Everything the collapses share for one decimation call (vcg passes it as the parameter
// object, so no static state: concurrent calls are safe).
struct Context : vcg::BaseParameterClass {
  VMesh* m = nullptr;
  DecimationOptions opt;
  double cos_normal = 0.5;
  double cos_fold = -0.5;       // cos(max_fold_deg): no face turns further, budget or not
  double cost_scale = 1.0;      // 1 / (bbox diagonal)^6: makes priorities scale-free floats
  double degenerate_area2 = 0;  // squared doubled-area below which a new face is degenerate
  int mark = 0;
  // Collapse counter and, per vertex, the counter value when its star last changed: an entry
  // evaluated after both its ends' stamps is still exact and need not be re-evaluated.
  int clock = 0;
  std::vector<int> stamp;

  std::vector<int> face_region, region_node, region_faces, face_component;
  std::vector<uint8_t> vclass;
  std::vector<char> contact_frozen;  // per vertex: a touching part's contact (contact_release.h), frozen
  std::vector<int> node_faces, node_target;
  std::vector<int> node_free_removed;  // faces lost to exact contour collapses past the budget
  std::vector<double> node_area, node_area0;
  std::vector<double> node_area_bound;  // per group: the bound on |area - area0| / area0 [-]
  std::vector<double> node_sharp;  // projected-area budget spent: steep turns and kinks run [m^2]
  std::vector<double> comp_volume, comp_volume0;
  std::vector<char> comp_closed;
  std::vector<double> comp_area0;  // per component: its input area [m^2] (wide kinks)
  std::vector<int> absorbed_by;  // removed face -> face that took over its area (provenance)
  std::vector<std::vector<int>> group_faces;  // input faces of each node group (restore_node_areas)
  std::vector<int> restore_slot;              // per vertex: its slot in a restoration plan, or -1
  // Per node group, with projected_area_cap: how far the collapses so far moved its projected
  // area P(d) = sum_f max(0, N_f . d) in each of kProjectionDirections directions d [m^2].
  static constexpr int kProjectionDirections = 64;
  using Projection = std::array<double, kProjectionDirections>;
  std::vector<Projection> node_projection_change;
  std::vector<VFace*> projection_faces;  // scratch for add_projection_change
  // With a reflected-sunlight cap (reflection_cap.cpp): per face, the reflected flux its front
  // and back carry now [W/m^2]; per node group, the reflected power the collapses so far moved
  // between its faces and the power it reflects [W].
  std::vector<std::array<double, 2>> face_flux;
  using View = std::vector<std::pair<int, double>>;  // (node, F) of one face side
  std::vector<std::array<View, 2>> face_view;
  // Per (source group n, receiving node g), at n * #nodes + g: how far the collapses of n's
  // faces moved the reflected power reaching g [W]. Per source, so that a node's decimation
  // does not depend on which other nodes are decimated with it (the search superposes them).
  std::vector<double> node_reflection_change_W;
  std::vector<double> reflection_scratch;        // per node, for one collapse [W]
  double reflection_cap_W(int node) const {
    return opt.reflection_cap * node_area_bound[node] * opt.reflection.node_absorbed_W[node];
  }
  //! The directions d: a Fibonacci lattice over the whole unit sphere (projected_area_cap.cpp).
  static const std::array<Vec3, kProjectionDirections>& projection_directions();
  // The cap on node `node`'s |P(d) - P0(d)| [m^2] (projected_area_cap).
  double projection_cap_m2(int node) const {
    return opt.projected_area_cap * node_area_bound[node] * node_area0[node];
  }
  std::vector<VFace*> star;      // scratch for evaluate()
  StarChange change;             // scratch for evaluate(): what the candidate does (its cost's input)
  std::vector<VVertex*> scratch_v[3];
  std::vector<std::pair<VVertex*, VVertex*>> scratch_e[2];
  std::vector<VVertex*> section_scratch[2];  // for the thin-tube section collapse
  void* heap = nullptr;          // vcg's heap, for re-queuing re-evaluated collapses
  // vcg's stopping face count (sum of the targets); free removals lower it by what they took,
  // since they do not bring any node closer to its target.
  int* target_simplices = nullptr;

  // The per-node area bound and the closed-part volume bound (open parts have none), for a
  // collapse that changes node `node`'s area by delta_m2 [m^2] or part `comp`'s volume by
  // delta_m3 [m^3] on top of what earlier collapses changed.
  bool area_within_bound(int node, double delta_m2) const {
    return std::abs(node_area[node] + delta_m2 - node_area0[node]) <= node_area_bound[node] * node_area0[node];
  }
  bool volume_within_bound(int comp, double delta_m3) const {
    return !comp_closed[comp] || std::abs(comp_volume[comp] + delta_m3 - comp_volume0[comp]) <=
                                     opt.max_relative_volume_change * std::abs(comp_volume0[comp]);
  }

  // The projected-area budget (DecimationOptions::projected_area_budget) of node `node` after a
  // collapse whose steep turns and contour kinks cost it delta_m2 [m^2] more.
  bool sharp_within_bound(int node, double delta_m2) const {
    return node_sharp[node] + delta_m2 <=
           opt.projected_area_budget * opt.max_relative_area_change * node_area0[node];
  }

  // Whether a surviving face may turn from doubled area vector n0 to n1 [m^2]: false if it
  // degenerates or turns past max_normal_deviation_deg (past max_fold_deg when steep turns
  // have a budget). `steep_m2` gets |N1 - N0| (N = n / 2) of a steep turn the node pays for,
  // 0 otherwise.
  bool turn_allowed(const Vec3& n0, const Vec3& n1, double& steep_m2) const {
    steep_m2 = 0;
    const double n1sq = n1.squaredNorm();
    if (n1sq <= degenerate_area2) return false;
    const double scale = std::sqrt(n0.squaredNorm() * n1sq);
    if (n0.dot(n1) >= cos_normal * scale) return true;
    if (!(opt.projected_area_budget > 0) || n0.dot(n1) < cos_fold * scale) return false;
    steep_m2 = 0.5 * (n1 - n0).norm();
    return true;
  }

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

//! Thermal node of face f, or `num_nodes` for the faces without one (one more group).
struct NodeGroups {
  const Mesh& mesh;
  int num_nodes;
  int operator()(int f) const { return mesh.face_node[f] >= 0 ? mesh.face_node[f] : num_nodes; }
};

//! Attribute of face f, or -1 if the (optional) per-face attribute is absent.
inline int attr(const Eigen::VectorXi& a, int f) { return a.size() > f ? a[f] : -1; }

//! The node/interface constraints of `mesh` in `c`: face regions (node, material, back
//! material) and their nodes and face counts, vertex classes (free, on one contour, frozen),
//! and the parts joined by manifold edges with their enclosed volumes [m^3] (closed parts
//! only count). Returns the number of parts.
int classify_mesh(const Mesh& mesh, const NodeGroups& group_of, Context& c);

}  // namespace thermodec::collapse
