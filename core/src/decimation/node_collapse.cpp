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
  refused_ = CollapseBlock::none;
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
    if (with_budget == 0 || (spent > 0 && !c.opt.free_exact_contour_collapses))
      return set_refused(CollapseBlock::neighbour_budget), _priority;
  }
  const uint8_t ca = c.vclass[c.vi(a)], cb = c.vclass[c.vi(b)];
  // On a thin tube, the whole cross-section goes (section_collapse.cpp), in the cheaper direction.
  if (c.opt.collapse_tube_sections && (ca == kFree || cb == kFree)) {
    NodeCollapse other = *this;
    const bool forward = ca == kFree && evaluate_section(c, a, b);
    const bool backward = cb == kFree && other.evaluate_section(c, b, a);
    if (backward && (!forward || other._priority < _priority)) *this = other;
    if (forward || backward) return _priority;
    if (on_thin_tube(c, a, b) || on_thin_tube(c, b, a)) return set_refused(CollapseBlock::thin_tube), _priority;
  }
  if (ca == kFree && cb == kFree) {
    evaluate(c, a, b, /*optimal=*/true);
  } else if (ca == kFree) {
    evaluate(c, a, b, false);
  } else if (cb == kFree) {
    evaluate(c, b, a, false);
  } else {
    // Both ends constrained: only along a contour edge, never between two frozen vertices.
    if ((ca == kFrozen && cb == kFrozen) || !is_contour_edge(c, a, b))
      return set_refused(CollapseBlock::frozen_vertices), _priority;
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
  if (section_.n == 0)
    for (vcg::face::VFIterator<VFace> it(gone); !it.End(); ++it)
      if (it.V1() == kept || it.V2() == kept) removed_faces.push_back(c.fi(it.F()));
  record_projection_change(c);  // before the collapse: it measures the star as it was
  record_reflection_change(c);   // likewise
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
  for (const auto& d : sharp_delta_) c.node_sharp[d.key] += d.value;
  for (const auto& d : volume_delta_) c.comp_volume[d.key] += d.value;
  if (section_.n > 0) return execute_section(m, c);
  vcg::tri::EdgeCollapser<VMesh, VPair>::Do(m, pos, vcg::Point3d(x_[0], x_[1], x_[2]));
  record_absorbed(c, removed_faces, kept);
  apply_area_restoration(c);
}

// Provenance: hand each removed face to a surviving face around the kept vertex, same
// region first (it covers the same node surface), else same node, else any.
void NodeCollapse::record_absorbed(Context& c, const std::vector<int>& removed_faces, VVertex* kept) {
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
  ++c.clock;
  // The kept vertex, or every vertex of a section collapse's kept loop.
  const int nkept = section_.n > 0 ? section_.n : 1;
  auto& edges = c.scratch_e[0];
  edges.clear();
  for (int j = 0; j < nkept; ++j) {
    VVertex* kept = section_.n > 0 ? section_.kept[j] : pos.V(1);
    kept->IMark() = c.mark;  // invalidates the old entries at the kept vertex
    c.stamp[c.vi(kept)] = c.clock;
    for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it)
      for (VVertex* r : {it.V1(), it.V2()}) {
        c.stamp[c.vi(r)] = c.clock;
        edges.emplace_back(std::min(kept, r), std::max(kept, r));
      }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) push(heap, a, b, c);
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
    if (!f.IsD())
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
