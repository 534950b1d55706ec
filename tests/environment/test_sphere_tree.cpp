// The blocker sphere tree (core/src/environment/sphere_tree.h, private to the core) must give
// exactly the answers of testing every member: it only prunes subtrees that cannot hold a
// passing member. Checked against brute force on random triangle soups, with the loads'
// own kind of query (a sphere swept along a direction, and "not below my plane").
#include <gtest/gtest.h>

#include <random>

#include "../../core/src/environment/sphere_tree.h"

namespace {

using Eigen::Vector3d;
using thermodec::blockers::SphereTree;

struct Soup {
  std::vector<Vector3d> a, b, c, centre;
  std::vector<double> radius;
};

Soup random_soup(int n, std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.001, 0.3);
  Soup s;
  for (int i = 0; i < n; ++i) {
    const Vector3d p(spread * u(rng), spread * u(rng), 0.2 * spread * u(rng));
    const double h = size(rng);
    s.a.push_back(p);
    s.b.push_back(p + h * Vector3d(u(rng), u(rng), u(rng)));
    s.c.push_back(p + h * Vector3d(u(rng), u(rng), u(rng)));
    s.centre.push_back((s.a[i] + s.b[i] + s.c[i]) / 3.0);
    s.radius.push_back(std::max({(s.a[i] - s.centre[i]).norm(), (s.b[i] - s.centre[i]).norm(),
                                 (s.c[i] - s.centre[i]).norm()}));
  }
  return s;
}

}  // namespace

TEST(SphereTree, swept_sphere_queries_match_testing_every_member) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 3, 17, 400}) {
    const Soup s = random_soup(n, rng, 5.0);
    std::vector<int> members(n);
    for (int i = 0; i < n; ++i) members[i] = i;
    const SphereTree tree = thermodec::blockers::sphere_tree(members, s.centre, s.radius, [&](int i, int k) -> const Vector3d& {
      return k == 0 ? s.a[i] : k == 1 ? s.b[i] : s.c[i];
    });
    int passed = 0;
    for (int q = 0; q < 300; ++q) {
      const int self = q % n;
      const Vector3d toward = Vector3d(u(rng), u(rng), u(rng)).normalized();
      const Vector3d normal = Vector3d(u(rng), u(rng), u(rng)).normalized();
      const Vector3d origin = s.centre[self];
      const double r0 = 0.05;
      // The shadow test of external_loads.cpp: the ball (centre, reach) meets the prism swept
      // by the querying sphere along `toward`.
      auto meets = [&](const Vector3d& centre, double reach) {
        const Vector3d v = centre - origin;
        const double along = v.dot(toward);
        return along >= -reach && v.squaredNorm() - along * along <= reach * reach;
      };
      auto above = [&](int t) {
        return normal.dot(s.a[t] - origin) > 0.0 || normal.dot(s.b[t] - origin) > 0.0 || normal.dot(s.c[t] - origin) > 0.0;
      };
      bool brute = false;
      for (int t = 0; t < n; ++t) brute |= t != self && above(t) && meets(s.centre[t], r0 + s.radius[t]);
      const bool fast = thermodec::blockers::any_member(
          tree,
          [&](const SphereTree::Node& node) {
            return thermodec::blockers::height_above_plane(node, normal, origin) > -1e-9 && meets(node.centre, r0 + node.radius);
          },
          [&](int t) { return t != self && above(t) && meets(s.centre[t], r0 + s.radius[t]); });
      ASSERT_EQ(fast, brute) << "n = " << n << ", query " << q;
      passed += brute;
    }
    if (n >= 17) EXPECT_GT(passed, 0) << "the queries must exercise both answers";
    if (n >= 17) EXPECT_LT(passed, 300) << "the queries must exercise both answers";
  }
}

TEST(SphereTree, every_node_sphere_holds_its_members_spheres) {
  std::mt19937 rng(11);
  const Soup s = random_soup(1000, rng, 50.0);
  std::vector<int> members(1000);
  for (int i = 0; i < 1000; ++i) members[i] = i;
  const SphereTree tree = thermodec::blockers::sphere_tree(members, s.centre, s.radius, [&](int i, int k) -> const Vector3d& {
    return k == 0 ? s.a[i] : k == 1 ? s.b[i] : s.c[i];
  });
  ASSERT_FALSE(tree.nodes.empty());
  EXPECT_EQ(tree.nodes[0].end - tree.nodes[0].begin, 1000);
  for (const auto& node : tree.nodes)
    for (int k = node.begin; k < node.end; ++k) {
      const int i = tree.items[k];
      EXPECT_LE((s.centre[i] - node.centre).norm() + s.radius[i], node.radius);
      for (const Vector3d* p : {&s.a[i], &s.b[i], &s.c[i]})
        EXPECT_TRUE((p->array() >= node.lo.array()).all() && (p->array() <= node.hi.array()).all());
    }
  EXPECT_TRUE(thermodec::blockers::sphere_tree({}, s.centre, s.radius, [&](int i, int) -> const Vector3d& { return s.a[i]; })
                  .nodes.empty());
}
