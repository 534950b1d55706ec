// The vcglib hooks of a candidate collapse: its priority (which collapses are tried, and in
// which order), execution with the budget and provenance bookkeeping, and the heap updates
// (lazy re-evaluation). Cost, placement and constraints live in their own files.
#include "node_collapse.h"

#include <algorithm>
#include <limits>

namespace thermodec::collapse {

NodeCollapse::ScalarType NodeCollapse::ComputePriority(vcg::BaseParameterClass* pp) {
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

void NodeCollapse::Execute(VMesh& m, vcg::BaseParameterClass* pp) {
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

void NodeCollapse::UpdateHeap(HeapType& heap, vcg::BaseParameterClass* pp) {
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

void NodeCollapse::push(HeapType& heap, VVertex* a, VVertex* b, Context& c) {
  auto* op = new NodeCollapse(VPair(a, b), c.mark, &c);
  if (!op->valid()) {
    delete op;
    return;
  }
  heap.push_back(HeapElem(op));
  std::push_heap(heap.begin(), heap.end());
}

void NodeCollapse::Init(VMesh& m, HeapType& heap, vcg::BaseParameterClass* pp) {
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

}  // namespace thermodec::collapse
