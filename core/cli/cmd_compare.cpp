// `thermodec compare A.json B.json`: max |dT| over nodes and times between two results.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "thermodec/thermal/result_json.h"

namespace thermodec::cli {

void add_compare(CLI::App& app) {
  auto a = std::make_shared<std::string>(), b = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* sub = app.add_subcommand(
      "compare", "compare two simulation results (thermodec simulate --json): max |dT| over nodes and times, "
                 "with the node and time where it occurs");
  sub->add_option("A", *a, "first result JSON")->required();
  sub->add_option("B", *b, "second result JSON")->required();
  sub->add_flag("--json", *json, "print the comparison as JSON");
  sub->callback([a, b, json] {
    run_guarded([&] {
      const TemperatureDifference d = compare_results(read_result(*a), read_result(*b));
      if (*json)
        std::printf("%s\n", nlohmann::json{{"max_abs_dT_K", d.max_abs_K},
                                           {"node", d.node},
                                           {"time_s", d.time_s},
                                           {"time_index", d.time_index}}
                                 .dump()
                                 .c_str());
      else
        std::printf("max |dT| = %.6g K at node %s, t = %.1f s (step %d)\n", d.max_abs_K, d.node.c_str(),
                    d.time_s, d.time_index);
    });
  });
}

}  // namespace thermodec::cli
