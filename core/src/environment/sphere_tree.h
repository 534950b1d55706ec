#pragma once
// Private to core/src/environment: a bounding-sphere tree over the faces that may block the
// sun or the Earth, for the conservative "can anything block this side's rays at all" tests
// of the external loads (may_be_shadowed, may_be_blocked_from_earth).
//
// Before it, every side kept the list of every face in front of its plane: O(faces^2) time
// and memory, 34 k sides x ~8 k faces on Juno's 17 k-face mesh (seconds and gigabytes per
// loads pass, and again in every reduction trial). The tree answers the same yes/no question
// in ~log(faces) node visits: a query prunes a subtree when the subtree's sphere (which holds
// every member's sphere) fails the caller's test, or when all its triangles lie below the
// querying side's plane. Members are then tested exactly as before, so the answers, and hence
// the loads, are bit-identical.
#include <Eigen/Core>

#include <algorithm>
#include <limits>
#include <vector>

namespace thermodec::blockers {

struct SphereTree {
  struct Node {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // sphere holding every member's sphere [m]
    double radius = 0.0;
    Eigen::Vector3d lo, hi;  // box of every member's triangle corners [m]
    int begin = 0, end = 0;  // members items[begin, end)
    int left = -1;           // children left and left + 1; -1 for a leaf
  };
  std::vector<Node> nodes;  // nodes[0] is the root (if any)
  std::vector<int> items;
};

//! Tree over items with sphere (centre[i], radius[i]) and triangle corners corner(i, k), k < 3.
template <class Corner>
SphereTree sphere_tree(const std::vector<int>& members, const std::vector<Eigen::Vector3d>& centre,
                       const std::vector<double>& radius, Corner&& corner, int leaf_size = 4) {
  SphereTree t;
  t.items = members;
  if (members.empty()) return t;
  t.nodes.reserve(2 * members.size() / std::max(1, leaf_size) + 2);
  // note: recursion depth ~log2(n / leaf_size): median splits.
  auto build = [&](auto&& self, int node, int begin, int end) -> void {
    Eigen::Vector3d clo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), chi = -clo;
    Eigen::Vector3d lo = clo, hi = chi;
    for (int k = begin; k < end; ++k) {
      const int i = t.items[k];
      clo = clo.cwiseMin(centre[i]);
      chi = chi.cwiseMax(centre[i]);
      for (int c = 0; c < 3; ++c) {
        lo = lo.cwiseMin(corner(i, c));
        hi = hi.cwiseMax(corner(i, c));
      }
    }
    const Eigen::Vector3d mid = 0.5 * (clo + chi);
    double r = 0.0;
    for (int k = begin; k < end; ++k) r = std::max(r, (centre[t.items[k]] - mid).norm() + radius[t.items[k]]);
    SphereTree::Node& n = t.nodes[node];
    n.centre = mid;
    n.radius = r * (1.0 + 1e-9) + 1e-12;  // rounding: the subtree test must never be stricter
    n.lo = lo;
    n.hi = hi;
    n.begin = begin;
    n.end = end;
    if (end - begin <= leaf_size) return;
    int axis;
    (chi - clo).maxCoeff(&axis);
    const int half = begin + (end - begin) / 2;
    std::nth_element(t.items.begin() + begin, t.items.begin() + half, t.items.begin() + end,
                     [&](int a, int b) { return centre[a][axis] < centre[b][axis]; });
    const int left = static_cast<int>(t.nodes.size());
    t.nodes.emplace_back();
    t.nodes.emplace_back();
    t.nodes[node].left = left;
    self(self, left, begin, half);
    self(self, left + 1, half, end);
  };
  t.nodes.emplace_back();
  build(build, 0, 0, static_cast<int>(members.size()));
  return t;
}

//! Largest n . (x - a) over the node's box: if it is <= h, every member triangle lies below
//! the plane through a with unit normal n (up to h).
inline double height_above_plane(const SphereTree::Node& node, const Eigen::Vector3d& n, const Eigen::Vector3d& a) {
  const Eigen::Vector3d mid = 0.5 * (node.lo + node.hi), half = 0.5 * (node.hi - node.lo);
  return n.dot(mid - a) + n.cwiseAbs().dot(half);
}

//! True if some member passes `member(i)`. `subtree(node)` must hold for a node whenever it
//! holds for one of its members (tests on the node's sphere that are monotone in the radius).
template <class Subtree, class Member>
bool any_member(const SphereTree& t, Subtree&& subtree, Member&& member) {
  if (t.nodes.empty()) return false;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const SphereTree::Node& n = t.nodes[stack[--top]];
    if (!subtree(n)) continue;
    if (n.left < 0) {
      for (int k = n.begin; k < n.end; ++k)
        if (member(t.items[k])) return true;
    } else {
      stack[top++] = n.left + 1;
      stack[top++] = n.left;
    }
  }
  return false;
}

}  // namespace thermodec::blockers
