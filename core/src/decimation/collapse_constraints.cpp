// The node and interface constraints of a collapse: per-node face budgets (with exact
// contour collapses for free), regions never emptied, the per-node area and closed-volume
// bounds, contour edges, and the link condition that keeps the topology.
//  T. Dey, H. Edelsbrunner et al., "Topology preserving edge contraction", 1999.
#include <algorithm>
#include <cmath>

#include "node_collapse.h"

namespace thermodec::collapse {

bool NodeCollapse::IsFeasible(vcg::BaseParameterClass* pp) {
  auto& c = *static_cast<Context*>(pp);
  // Lazy re-evaluation: after a collapse only the edges at the kept vertex are re-queued;
  // other entries whose stars changed are re-evaluated here when they surface. If the cost
  // rose, the collapse goes back into the heap at its new priority instead of running now.
  const ScalarType stored = _priority;
  if (!is_fresh(c)) ComputePriority(pp);
  if (!valid_) return false;
  if (_priority > stored) {
    auto& heap = *static_cast<HeapType*>(c.heap);
    heap.push_back(HeapElem(new NodeCollapse(*this)));
    std::push_heap(heap.begin(), heap.end());
    return false;
  }
  return constraints_hold(c);
}

bool NodeCollapse::constraints_hold(Context& c) {
  auto refuse = [&](CollapseBlock why) { return refused_ = why, false; };
  // Budgets: each node pays for its removed faces, except one whose geometry the collapse
  // leaves unchanged (exact_per_node_); somebody must pay, or the collapse serves no one.
  bool paid = false;
  for (const auto& d : removed_per_node_) {
    if (c.node_faces[d.key] - static_cast<int>(d.value) >= c.node_target[d.key])
      paid = true;
    else if (!is_exact_for(d.key) || c.node_faces[d.key] - static_cast<int>(d.value) < c.opt.min_faces_per_node)
      return refuse(CollapseBlock::neighbour_budget);
  }
  if (!paid) return refuse(CollapseBlock::neighbour_budget);
  for (const auto& d : removed_per_region_)
    if (c.region_faces[d.key] - static_cast<int>(d.value) < 1) return refuse(CollapseBlock::last_region_face);
  // A node past its area bound may have its area restored by its free vertices
  // (restore_node_areas, area_restoration.cpp); at most one node per collapse.
  restore_ = Restoration();
  int past_bound = -1;
  for (const auto& d : area_delta_)
    if (!c.area_within_bound(d.key, d.value)) {
      if (past_bound >= 0) return refuse(CollapseBlock::area_bound);
      past_bound = d.key;
    }
  if (past_bound >= 0 && !plan_area_restoration(c, past_bound)) return refuse(CollapseBlock::area_bound);
  // With a projected-area cap, what the collapse does to each node's projected area is measured
  // and capped; the budget's account, a bound on its steep part, no longer refuses.
  const bool capped = !c.node_projection_change.empty();
  for (const auto& d : sharp_delta_)
    if (!capped && !c.sharp_within_bound(d.key, d.value)) return refuse(CollapseBlock::projected_area_budget);
  for (const auto& d : volume_delta_) {
    double restored = 0;
    for (const auto& e : restore_.volume)
      if (e.key == d.key) restored = e.value;
    if (!c.volume_within_bound(d.key, d.value + restored)) return refuse(CollapseBlock::volume_bound);
  }
  if (capped)
    for (const auto& d : area_delta_)
      if (!projection_within_cap(c, d.key)) return refuse(CollapseBlock::projected_area_budget);
  if (!reflection_within_cap(c)) return refuse(CollapseBlock::reflected_sunlight);
  // A section collapse checked its topology when it was evaluated (section_collapse.cpp).
  if (section_.n == 0 && !link_condition(c)) return refuse(CollapseBlock::topology);
  refused_ = CollapseBlock::none;
  return true;
}

bool NodeCollapse::is_fresh(const Context& c) const {
  auto unchanged = [&](const VVertex* v) { return !v->IsD() && c.stamp[c.vi(v)] <= evaluated_at_; };
  if (!unchanged(pos.cV(0)) || !unchanged(pos.cV(1))) return false;
  for (int j = 0; j < section_.n; ++j)
    if (!unchanged(section_.gone[j]) || !unchanged(section_.kept[j])) return false;
  return true;
}

bool NodeCollapse::is_contour_edge(const Context& c, VVertex* a, VVertex* b) {
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

VVertex* NodeCollapse::other_contour_neighbour(const Context& c, VVertex* v, VVertex* not_this) {
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

bool NodeCollapse::link_condition(Context& c) const {
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

}  // namespace thermodec::collapse
