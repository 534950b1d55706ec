// Merging nodes on a ThermalModel (nodes/merge_nodes.h): the arithmetic by hand, on the sample.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "common/scratch_dir.h"
#include "thermodec/common/errors.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/nodes/merge_nodes.h"

namespace fs = std::filesystem;
using namespace thermodec;

namespace {

const fs::path kSample = fs::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite" / "model.json";

int node_index(const ThermalModel& m, const std::string& name) {
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

// Labels merging the named nodes into the first of them.
NodeMergeMap merging(const ThermalModel& m, const std::vector<std::string>& group) {
  std::vector<int> label(m.nodes.size());
  for (std::size_t i = 0; i < label.size(); ++i) label[i] = static_cast<int>(i);
  for (const auto& g : group) label[node_index(m, g)] = node_index(m, group.front());
  return node_merge_map(label, static_cast<int>(m.nodes.size()));
}

double link(const ThermalModel& m, const std::string& a, const std::string& b) {
  double g = 0.0;
  const int ia = node_index(m, a), ib = node_index(m, b);
  for (const Conductance& c : m.conductances)
    if ((c.from == ia && c.to == ib) || (c.from == ib && c.to == ia)) g += c.conductance_W_per_K;
  return g;
}

}  // namespace

TEST(MergeNodes, identity_map_keeps_every_node_in_place) {
  const NodeMergeMap map = node_merge_map({0, 1, 2}, 3);
  EXPECT_EQ(map.num_merged(), 3);
  EXPECT_EQ(map.merged_of_node, (std::vector<int>{0, 1, 2}));
  const NodeMergeMap m2 = node_merge_map({7, 3, 7, 3}, 4);
  EXPECT_EQ(m2.merged_of_node, (std::vector<int>{0, 1, 0, 1}));
  EXPECT_EQ(m2.members[0], (std::vector<int>{0, 2}));
  EXPECT_THROW(node_merge_map({0, 1}, 3), InvalidInput);
}

TEST(MergeNodes, capacitances_powers_and_outside_links_are_summed_inner_links_dropped) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = load_model(kSample);
  const std::vector<std::string> group{"body_px", "body_py", "body_pz"};
  const ThermalModel merged = merge_nodes(m, merging(m, group));
  ASSERT_EQ(merged.nodes.size(), m.nodes.size() - 2);
  const int g = node_index(merged, "body_px+2");
  ASSERT_GE(g, 0);
  double c = 0.0, q = 0.0;
  for (const auto& n : group) c += m.nodes[node_index(m, n)].capacitance_J_per_K, q += m.nodes[node_index(m, n)].power_W;
  EXPECT_DOUBLE_EQ(merged.nodes[g].capacitance_J_per_K, c);
  EXPECT_DOUBLE_EQ(merged.nodes[g].power_W, q);
  // Every link to a node outside the group is summed; none stays between members.
  for (const Node& other : merged.nodes) {
    if (other.name == "body_px+2") continue;
    double expected = 0.0;
    for (const auto& n : group) expected += link(m, n, other.name);
    EXPECT_DOUBLE_EQ(link(merged, "body_px+2", other.name), expected) << other.name;
  }
  for (const Conductance& l : merged.conductances) EXPECT_NE(l.from, l.to);
  // One link per pair of merged nodes.
  for (std::size_t a = 0; a < merged.conductances.size(); ++a)
    for (std::size_t b = a + 1; b < merged.conductances.size(); ++b)
      EXPECT_FALSE(std::minmax(merged.conductances[a].from, merged.conductances[a].to) ==
                   std::minmax(merged.conductances[b].from, merged.conductances[b].to));
  // Total capacitance, power and outside conductance are conserved.
  double c_all = 0.0, c_merged = 0.0;
  for (const Node& n : m.nodes) c_all += n.capacitance_J_per_K;
  for (const Node& n : merged.nodes) c_merged += n.capacitance_J_per_K;
  EXPECT_DOUBLE_EQ(c_merged, c_all);
}

TEST(MergeNodes, faces_are_relabelled_on_the_one_mesh_keeping_their_coatings) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = load_model(kSample);
  const ThermalModel merged = merge_nodes(m, merging(m, {"body_mx", "body_my"}));
  ASSERT_EQ(merged.mesh.num_faces(), m.mesh.num_faces());
  EXPECT_TRUE(merged.mesh.F == m.mesh.F);
  EXPECT_TRUE(merged.mesh.V == m.mesh.V);
  EXPECT_TRUE(merged.mesh.face_material == m.mesh.face_material);
  EXPECT_TRUE(merged.mesh.face_back_material == m.mesh.face_back_material);
  EXPECT_EQ(merged.mesh.node_names.size(), merged.nodes.size());
  const int g = node_index(merged, "body_mx+1");
  for (int f = 0; f < m.mesh.num_faces(); ++f) {
    const std::string& was = m.nodes[m.mesh.face_node[f]].name;
    const std::string& now = merged.nodes[merged.mesh.face_node[f]].name;
    if (was == "body_mx" || was == "body_my") EXPECT_EQ(merged.mesh.face_node[f], g);
    else EXPECT_EQ(now, was);
  }
}

TEST(MergeNodes, node_map_names_each_original_node_and_survives_save_and_load) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = load_model(kSample);
  const ThermalModel merged = merge_nodes(m, merging(m, {"body_mx", "body_my"}));
  ASSERT_EQ(merged.node_map.size(), m.nodes.size());
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    EXPECT_EQ(merged.node_map[i].first, m.nodes[i].name);
    const bool in = m.nodes[i].name == "body_mx" || m.nodes[i].name == "body_my";
    EXPECT_EQ(merged.node_map[i].second, in ? "body_mx+1" : m.nodes[i].name);
  }
  // Merging a merged model composes the maps: original -> latest node.
  const ThermalModel twice = merge_nodes(merged, merging(merged, {"body_mx+1", "body_px"}));
  for (const auto& [original, into] : twice.node_map)
    if (original == "body_mx" || original == "body_my" || original == "body_px") EXPECT_EQ(into, "body_px+1");
  const fs::path d = test::scratch_dir("thermodec_test_merge", "round_trip");
  save_model(twice, d / "m.json", d / "m.obj");
  const ThermalModel back = load_model(d / "m.json");
  ASSERT_EQ(back.nodes.size(), twice.nodes.size());
  std::map<std::string, std::string> a(twice.node_map.begin(), twice.node_map.end()),
      b(back.node_map.begin(), back.node_map.end());
  EXPECT_EQ(a, b);
  EXPECT_TRUE(back.mesh.face_material == twice.mesh.face_material);
}

TEST(MergeNodes, fixed_temperature_nodes_are_never_merged) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  ThermalModel m = load_model(kSample);
  m.nodes[node_index(m, "body_px")].fixed_temperature_K = 290.0;
  EXPECT_THROW(merge_nodes(m, merging(m, {"body_px", "body_mx"})), InvalidInput);
  EXPECT_NO_THROW(merge_nodes(m, merging(m, {"body_py", "body_mx"})));
}

TEST(MergeNodes, keep_patterns_match_names_and_unknown_ones_are_refused) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = load_model(kSample);
  const std::vector<int> body = nodes_matching(m, {"body_*"});
  EXPECT_EQ(body.size(), 6u);
  EXPECT_EQ(nodes_matching(m, {"dish", "dish"}), (std::vector<int>{node_index(m, "dish")}));
  try {
    nodes_matching(m, {"antenna"});
    ADD_FAILURE() << "accepted a pattern matching nothing";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("antenna"), std::string::npos);
  }
}

TEST(MergeNodes, merged_names_stay_unique) {
  EXPECT_EQ(merged_node_name({"a"}, {}), "a");
  EXPECT_EQ(merged_node_name({"a", "b", "c"}, {}), "a+2");
  EXPECT_EQ(merged_node_name({"a", "b"}, {"a+1"}), "a+1_2");
}
