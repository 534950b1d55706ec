// The cost check every simulating command runs before its expensive work (commands.h).
#include <iostream>

#include "commands.h"
#include "thermodec/common/errors.h"

namespace thermodec::cli {

void guard_simulation_cost(const std::string& command, const ThermalModel& model,
                           const ModelSimulationSettings& settings, bool quiet, const std::vector<LoadCase>& cases,
                           SimulationCostScope scope) {
  std::vector<LoadCase> all{own_case(model)};
  all.insert(all.end(), cases.begin(), cases.end());
  for (const LoadCase& c : all) {
    const ThermalModel m = cases.empty() ? model : with_case(model, c);
    const SimulationCost cost = simulation_cost(m, settings, scope);
    const std::string which = cases.empty() ? std::string() : " (case " + c.name + ")";
    if (!quiet)
      std::cerr << command << ": estimated cost" << which << ": " << cost.summary() << "\n";
    const std::string excess = simulation_cost_excess(cost, m, settings);
    if (excess.empty()) continue;
    if (!force_costly_runs())
      throw InvalidInput("estimated cost" + which + " over the limit: " + excess +
                         "; lower that setting, or pass --force to run anyway (docs/model-format.md, \"Validation\")");
    std::cerr << command << ": warning: estimated cost" << which << " over the limit, running anyway (--force): "
              << excess << "\n";
  }
}

}  // namespace thermodec::cli
