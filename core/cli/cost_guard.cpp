// The cost check every simulating command runs before its expensive work (commands.h): the
// core's check_simulation_cost (thermal/simulation_cost.h), printed, with the CLI's --force.
#include <iostream>

#include "commands.h"

namespace thermodec::cli {

void guard_simulation_cost(const std::string& command, const SimulationCostCheck& check, bool quiet) {
  if (!quiet)
    for (const std::string& line : check.estimates) std::cerr << command << ": " << line << "\n";
  refuse_costly_run(check, force_costly_runs(), "pass --force to run anyway");
  if (!check.excess.empty())
    std::cerr << command << ": warning: estimated cost" << check.excess_case
              << " over the limit, running anyway (--force): " << check.excess << "\n";
}

}  // namespace thermodec::cli
