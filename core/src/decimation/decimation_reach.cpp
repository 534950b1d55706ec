// Decimation reach: why a node ended above its target. After the collapses, every edge of a
// node still short of its target is evaluated once more, as a collapse would be, and the
// first check that refuses it is counted for that node. Read-only: the coarse mesh is the
// same with or without it.
#include <algorithm>

#include "node_collapse.h"

namespace thermodec {

const char* collapse_block_name(CollapseBlock block) {
  switch (block) {
    case CollapseBlock::neighbour_budget: return "neighbour_budget";
    case CollapseBlock::last_region_face: return "last_region_face";
    case CollapseBlock::area_bound: return "area_bound";
    case CollapseBlock::volume_bound: return "volume_bound";
    case CollapseBlock::contour_deviation: return "contour_deviation";
    case CollapseBlock::frozen_vertices: return "frozen_vertices";
    case CollapseBlock::normal_deviation: return "normal_deviation";
    case CollapseBlock::topology: return "topology";
    case CollapseBlock::thin_tube: return "thin_tube";
    case CollapseBlock::projected_area_budget: return "projected_area_budget";
    case CollapseBlock::reflected_sunlight: return "reflected_sunlight";
    case CollapseBlock::none: return "none";
  }
  return "none";
}

CollapseBlock NodeDecimationStats::stopped_by() const {
  int best = static_cast<int>(CollapseBlock::none), most = 0;
  for (int k = 0; k < kCollapseBlocks; ++k)
    if (blocked_edges[k] > most) best = k, most = blocked_edges[k];
  return static_cast<CollapseBlock>(best);
}

namespace collapse {

std::vector<std::array<int, kCollapseBlocks>> explain_reach(VMesh& m, Context& c) {
  const int groups = static_cast<int>(c.node_faces.size());
  std::vector<std::array<int, kCollapseBlocks>> blocked(groups);
  for (auto& b : blocked) b.fill(0);
  auto short_of_target = [&](int g) { return c.node_faces[g] > c.node_target[g]; };
  bool any = false;
  for (int g = 0; g < groups; ++g) any |= short_of_target(g);
  if (!any) return blocked;
  std::vector<std::pair<VVertex*, VVertex*>> edges;
  for (auto& f : m.face)
    if (!f.IsD() && short_of_target(c.region_node[c.face_region[c.fi(&f)]]))
      for (int j = 0; j < 3; ++j) edges.emplace_back(std::min(f.V0(j), f.V1(j)), std::max(f.V0(j), f.V1(j)));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) {
    NodeCollapse op(VPair(a, b), c.mark, &c);
    if (op.valid()) op.constraints_hold(c);
    const int why = static_cast<int>(op.refused());
    std::array<int, 4> counted{};
    int ncounted = 0;
    for (vcg::face::VFIterator<VFace> it(a); !it.End(); ++it) {
      if (it.V1() != b && it.V2() != b) continue;
      const int g = c.region_node[c.face_region[c.fi(it.F())]];
      if (!short_of_target(g) || std::find(counted.begin(), counted.begin() + ncounted, g) != counted.begin() + ncounted)
        continue;
      if (ncounted < 4) counted[ncounted++] = g;
      ++blocked[g][why];
    }
  }
  return blocked;
}

}  // namespace collapse
}  // namespace thermodec
