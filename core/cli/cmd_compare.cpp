// `thermodec compare A.json B.json [--tolerance K]`: max |dT| over nodes and times between two
// results, per node and overall. With --tolerance the exit code says whether it holds (3 when
// exceeded), so a thermal model's CI can run it. A node whose difference lies within 2 sigma of
// the two results' sampling noise (summary.<node>.noise_K, added in quadrature) is marked as such.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/reduction/merged_network.h"
#include "thermodec/thermal/result_json.h"

namespace thermodec::cli {

//! Exit code of `compare --tolerance` when the largest |dT| exceeds it (1 stays "bad input").
constexpr int kToleranceExceededExitCode = 3;

namespace {
// The "node_map" (original -> merged) a result of a merged model carries (simulate --json), if any.
std::vector<std::pair<std::string, std::string>> result_node_map(const std::string& path) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  std::vector<std::pair<std::string, std::string>> map;
  if (!j.is_object() || !j.contains("node_map") || !j.at("node_map").is_object()) return map;
  for (const auto& item : j.at("node_map").items()) {
    if (!item.value().is_string()) throw InvalidInput(path + ": 'node_map." + item.key() + "' must be a node name");
    map.emplace_back(item.key(), item.value().get<std::string>());
  }
  return map;
}
}  // namespace

void add_compare(CLI::App& app) {
  auto a = std::make_shared<std::string>(), b = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto tolerance = std::make_shared<double>(-1.0);
  auto* sub = app.add_subcommand(
      "compare", "compare two simulation results (thermodec simulate --json): max |dT| per node and overall, "
                 "with the time where it occurs; --tolerance K exits 3 when exceeded. A merged model's result "
                 "(its node_map) is compared with its original's node by node through the map");
  sub->add_option("A", *a, "first result JSON")->required();
  sub->add_option("B", *b, "second result JSON")->required();
  sub->add_flag("--json", *json, "print the comparison as JSON");
  sub->add_option("--tolerance", *tolerance, "largest acceptable |dT| [K]: exit code 3 when exceeded")
      ->check(CLI::NonNegativeNumber);
  sub->callback([a, b, json, tolerance] {
    bool exceeded = false;
    run_guarded([&] {
      SimulationResult ra = read_result(*a), rb = read_result(*b);
      // A merged model's result against its original's: each original node against the node it
      // was merged into (when only one side is merged).
      const auto map_a = result_node_map(*a), map_b = result_node_map(*b);
      if (!map_a.empty() && map_b.empty()) ra = result_through_node_map(ra, map_a);
      if (!map_b.empty() && map_a.empty()) rb = result_through_node_map(rb, map_b);
      const TemperatureDifference d = compare_results(ra, rb);
      // One standard deviation of the difference per node: the two results' noise in quadrature
      // (independent draws); nodes neither result states a noise for get none.
      std::map<std::string, double> noise;
      for (const SimulationResult* r : {&ra, &rb})
        for (std::size_t i = 0; i < r->nodes.size() && r->noise_K.size() == static_cast<Eigen::Index>(r->nodes.size()); ++i)
          noise[r->nodes[i]] += r->noise_K[i] * r->noise_K[i];
      auto sigma = [&](const std::string& node) { const auto it = noise.find(node); return it == noise.end() ? -1.0 : std::sqrt(it->second); };
      auto within_noise = [&](const TemperatureDifference::PerNode& n) { return sigma(n.node) >= 0.0 && n.max_abs_K <= 2.0 * sigma(n.node); };
      exceeded = *tolerance >= 0.0 && !(d.max_abs_K <= *tolerance);
      if (*json) {
        nlohmann::json nodes = nlohmann::json::array();
        for (const auto& n : d.per_node) {
          nodes.push_back({{"node", n.node}, {"max_abs_dT_K", n.max_abs_K}, {"time_s", n.time_s}});
          if (sigma(n.node) >= 0.0) nodes.back()["noise_K"] = sigma(n.node), nodes.back()["within_2_sigma_noise"] = within_noise(n);
        }
        nlohmann::json j{{"max_abs_dT_K", d.max_abs_K}, {"node", d.node}, {"time_s", d.time_s},
                         {"time_index", d.time_index}, {"nodes", nodes}};
        if (*tolerance >= 0.0) j["tolerance_K"] = *tolerance, j["within_tolerance"] = !exceeded;
        std::printf("%s\n", j.dump().c_str());
        return;
      }
      const bool any_noise = !noise.empty();
      std::printf("%-24s %12s %12s%s\n", "node", "max |dT| K", "at t [s]", any_noise ? "  noise 1-sigma K" : "");
      for (const auto& n : d.per_node) {
        std::printf("%-24s %12.6g %12.1f", n.node.c_str(), n.max_abs_K, n.time_s);
        if (any_noise) sigma(n.node) >= 0.0 ? std::printf("  %15.3g", sigma(n.node)) : std::printf("  %15s", "-");
        std::printf("%s%s\n", within_noise(n) ? "  within 2 sigma of noise" : "",
                    *tolerance >= 0.0 && !(n.max_abs_K <= *tolerance) ? "  exceeds tolerance" : "");
      }
      std::printf("max |dT| = %.6g K at node %s, t = %.1f s (step %d)\n", d.max_abs_K, d.node.c_str(),
                  d.time_s, d.time_index);
      if (*tolerance >= 0.0)
        std::printf("%s tolerance %.6g K\n", exceeded ? "EXCEEDS" : "within", *tolerance);
    });
    if (exceeded && exit_code() == 0) set_exit_code(kToleranceExceededExitCode);
  });
}

}  // namespace thermodec::cli
