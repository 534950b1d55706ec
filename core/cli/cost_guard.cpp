// The cost check every simulating command runs before its expensive work (commands.h).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/physical_memory.h"

namespace thermodec::cli {
namespace {

std::string gib(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / double(1ull << 30));
  return buf;
}

// The view-factor rows are an upper bound that geometry decides how far below it they stay;
// beyond the machine's memory, a run may be killed by the system after hours of work.
std::string memory_excess(const SimulationCost& c) {
  const double machine = double(physical_memory_bytes());
  const double need = c.memory_bytes() + c.view_factor_bytes_max;
  if (machine <= 0.0 || need <= machine) return {};
  return "memory up to " + gib(need) + " (view-factor rows up to " + gib(c.view_factor_bytes_max) +
         ": radiation.rays_per_face over " + std::to_string(c.sides) + " face sides) is more than this machine's " +
         gib(machine);
}

}  // namespace

void guard_simulation_cost(const std::string& command, const ThermalModel& model,
                           const ModelSimulationSettings& settings, bool quiet, const std::vector<LoadCase>& cases,
                           SimulationCostScope scope, const NoiseTargetingBound& noise) {
  std::vector<LoadCase> all{own_case(model)};
  all.insert(all.end(), cases.begin(), cases.end());
  for (const LoadCase& c : all) {
    const ThermalModel m = cases.empty() ? model : with_case(model, c);
    SimulationCost cost = simulation_cost(m, settings, scope);
    if (noise.max_extra > 0.0) cost = noise_targeted_cost(cost, noise.max_extra, noise.max_samples);
    const std::string which = cases.empty() ? std::string() : " (case " + c.name + ")";
    if (!quiet)
      std::cerr << command << ": estimated cost" << which << (noise.max_extra > 0.0 ? " with noise-targeted sampling" : "")
                << ": " << cost.summary() << "\n";
    std::string excess = simulation_cost_excess(cost, m, settings);
    if (excess.empty()) excess = memory_excess(cost);
    if (excess.empty()) continue;
    if (!force_costly_runs())
      throw InvalidInput("estimated cost" + which + " over the limit: " + excess +
                         "; lower that setting, or pass --force to run anyway (docs/model-format.md, \"Validation\")");
    std::cerr << command << ": warning: estimated cost" << which << " over the limit, running anyway (--force): "
              << excess << "\n";
  }
}

}  // namespace thermodec::cli
