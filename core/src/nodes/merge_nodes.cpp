#include "thermodec/nodes/merge_nodes.h"

#include <algorithm>
#include <fnmatch.h>
#include <map>
#include <utility>

#include "thermodec/common/errors.h"

namespace thermodec {

NodeMergeMap node_merge_map(const std::vector<int>& group_of_node, int num_nodes) {
  if (static_cast<int>(group_of_node.size()) != num_nodes)
    throw InvalidInput("node merge: " + std::to_string(group_of_node.size()) + " group labels for " +
                       std::to_string(num_nodes) + " nodes");
  NodeMergeMap map;
  map.merged_of_node.assign(num_nodes, -1);
  std::map<int, int> merged_of_label;  // label -> merged index, in order of first member
  for (int i = 0; i < num_nodes; ++i) {
    const auto it = merged_of_label.emplace(group_of_node[i], map.num_merged()).first;
    if (it->second == map.num_merged()) map.members.emplace_back();
    map.merged_of_node[i] = it->second;
    map.members[it->second].push_back(i);
  }
  return map;
}

std::string merged_node_name(const std::vector<std::string>& member_names, const std::vector<std::string>& taken) {
  if (member_names.empty()) throw InvalidInput("node merge: a merged node needs at least one member");
  std::string name = member_names.front();
  if (member_names.size() > 1) name += "+" + std::to_string(member_names.size() - 1);
  const std::string base = name;
  for (int k = 2; std::find(taken.begin(), taken.end(), name) != taken.end(); ++k) name = base + "_" + std::to_string(k);
  return name;
}

ThermalModel merge_nodes(const ThermalModel& model, const NodeMergeMap& map) {
  const int n = static_cast<int>(model.nodes.size());
  if (static_cast<int>(map.merged_of_node.size()) != n)
    throw InvalidInput("node merge: the map covers " + std::to_string(map.merged_of_node.size()) + " nodes, the model has " +
                       std::to_string(n));
  ThermalModel out = model;
  out.nodes.clear();
  out.conductances.clear();
  std::vector<std::string> names;
  for (const auto& members : map.members) {
    std::vector<std::string> member_names;
    Node merged = model.nodes.at(members.front());
    merged.capacitance_J_per_K = 0.0;
    merged.power_W = 0.0;
    for (int i : members) {
      const Node& nd = model.nodes.at(i);
      if (nd.fixed_temperature_K && members.size() > 1)
        throw InvalidInput("node '" + nd.name + "' has a fixed temperature and cannot be merged with other nodes");
      member_names.push_back(nd.name);
      merged.capacitance_J_per_K += nd.capacitance_J_per_K;
      merged.power_W += nd.power_W;
      merged.sampling_boost.ir = std::max(merged.sampling_boost.ir, nd.sampling_boost.ir);
      merged.sampling_boost.loads = std::max(merged.sampling_boost.loads, nd.sampling_boost.loads);
    }
    // Names of single nodes are kept as they are; a merged one must not take a kept name.
    std::vector<std::string> taken = names;
    for (int i = 0; i < n; ++i)
      if (members.size() > 1 || i != members.front()) taken.push_back(model.nodes[i].name);
    merged.name = members.size() == 1 ? member_names.front() : merged_node_name(member_names, taken);
    names.push_back(merged.name);
    out.nodes.push_back(merged);
  }
  // Links summed per merged pair, in order of first appearance (deterministic output).
  std::map<std::pair<int, int>, std::size_t> link_of_pair;
  for (const Conductance& c : model.conductances) {
    if (c.from < 0 || c.from >= n || c.to < 0 || c.to >= n) throw InvalidInput("node merge: a conductance names no node");
    const int a = map.merged_of_node[c.from], b = map.merged_of_node[c.to];
    if (a == b) continue;  // inside one isothermal node: no temperature difference to conduct
    const auto key = std::minmax(a, b);
    const auto it = link_of_pair.find(key);
    if (it == link_of_pair.end()) {
      link_of_pair.emplace(key, out.conductances.size());
      out.conductances.push_back({a, b, c.conductance_W_per_K});
    } else {
      out.conductances[it->second].conductance_W_per_K += c.conductance_W_per_K;
    }
  }
  // The one shared mesh is relabelled, never split: faces keep material and sidedness.
  for (int f = 0; f < out.mesh.num_faces(); ++f) {
    const int nd = out.mesh.face_node[f];
    if (nd >= 0 && nd < n) out.mesh.face_node[f] = map.merged_of_node[nd];
  }
  out.mesh.node_names = names;
  // original -> merged, through the input's own map when it is itself a merged model.
  out.node_map.clear();
  if (model.node_map.empty()) {
    for (int i = 0; i < n; ++i) out.node_map.emplace_back(model.nodes[i].name, names[map.merged_of_node[i]]);
  } else {
    std::vector<std::string> current;
    for (const Node& nd : model.nodes) current.push_back(nd.name);
    const std::vector<int> idx = merged_index_of_original(model.node_map, current);
    for (std::size_t k = 0; k < model.node_map.size(); ++k)
      out.node_map.emplace_back(model.node_map[k].first, names[map.merged_of_node[idx[k]]]);
  }
  return out;
}

std::vector<int> nodes_matching(const ThermalModel& model, const std::vector<std::string>& patterns) {
  std::vector<int> out;
  for (const std::string& p : patterns) {
    bool any = false;
    for (int i = 0; i < static_cast<int>(model.nodes.size()); ++i)
      if (fnmatch(p.c_str(), model.nodes[i].name.c_str(), 0) == 0) {
        any = true;
        out.push_back(i);
      }
    if (!any) throw InvalidInput("node pattern '" + p + "' matches no node of the model");
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> merged_index_of_original(const std::vector<std::pair<std::string, std::string>>& node_map,
                                          const std::vector<std::string>& merged_names) {
  std::vector<int> out;
  for (const auto& [original, merged] : node_map) {
    const auto it = std::find(merged_names.begin(), merged_names.end(), merged);
    if (it == merged_names.end())
      throw InvalidInput("node_map: original node '" + original + "' maps to '" + merged + "', which is not a node of the model");
    out.push_back(static_cast<int>(it - merged_names.begin()));
  }
  return out;
}

}  // namespace thermodec
