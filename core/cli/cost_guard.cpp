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

// Noise-targeted sampling runs the model once at its own counts to estimate the noise, then
// again with the boosts, whose extra samples of each kind are capped at max_extra x the model's
// total and at max_samples (thermal/simulate_model.h): the estimate takes both runs at those
// caps. A sun sample is traced at every shadow pass, so its cap counts once per pass.
void add_noise_targeting(SimulationCost& c, const NoiseTargetingBound& noise) {
  const auto boosted = [&](double base, double passes) {
    return 2.0 * base + std::min(noise.max_extra * base, noise.max_samples * passes);
  };
  c.ir_rays = boosted(c.ir_rays, 1.0);
  c.sun_rays = boosted(c.sun_rays, std::max(1, c.shadow_passes));
  c.earth_ray_tests *= 2.0 + noise.max_extra;
  c.earth_rays = boosted(c.earth_rays, 1.0);
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
    if (noise.max_extra > 0.0) add_noise_targeting(cost, noise);
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
