#pragma once
//! How a side picks its control hulls and their joint shares, shared by the view-factor rows
//! (side_strata, planar_strata.h) and the direct sun's shadows (environment/shadow_controls.h):
//! only the share of a set of hulls differs between them.
#include <Eigen/Core>
#include <algorithm>
#include <utility>
#include <vector>

#include "thermodec/radiation/planar_strata.h"

namespace thermodec {

//! The side's strata from its candidates (share U, hull index), every one in [min_share,
//! 1 - min_share] already: the kMaxStrataPerSide largest by share (ties: order given), then
//! SideStrata::joint of every set of two or more of them from share_of(polygons of the set)
//! [-]. A set holding a smaller one that no ray crosses together (joint 0) is 0 without a call.
template <class ShareOf>
SideStrata side_strata_of(std::vector<std::pair<double, int>>& cand, const std::vector<NodeHull>& hulls,
                          const ShareOf& share_of) {
  std::stable_sort(cand.begin(), cand.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  SideStrata st;
  for (const auto& [u, k] : cand) {
    if (st.count == kMaxStrataPerSide) break;
    st.hull[st.count] = k;
    st.share[st.count] = u;
    st.joint[1 << st.count] = u;
    ++st.count;
  }
  const int M = 1 << st.count;
  for (int set = 1; set < M; ++set) {
    if ((set & (set - 1)) == 0) continue;  // one hull: its share
    bool empty = false;
    for (int k = 0; k < st.count && !empty; ++k)
      if (set >> k & 1) empty = st.joint[set & ~(1 << k)] == 0.0;
    if (empty) continue;
    std::vector<std::vector<Eigen::Vector3d>> ps;
    for (int k = 0; k < st.count; ++k)
      if (set >> k & 1) ps.push_back(hulls[st.hull[k]].vertices);
    st.joint[set] = share_of(ps);
  }
  return st;
}

}  // namespace thermodec
