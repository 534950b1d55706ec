#include "thermodec/thermal/internal_power.h"

#include <algorithm>
#include <sstream>
#include <vector>

#include "thermodec/common/errors.h"

namespace thermodec {

namespace {

void check_times(const ThermalNetwork& net, double P) {
  if (!(P > 0.0)) throw InvalidInput("power schedules need an orbit period > 0 s");
  for (std::size_t i = 0; i < net.power_schedule_W.size(); ++i)
    for (const auto& entry : net.power_schedule_W[i])
      if (!(entry.first < P)) {
        std::ostringstream m;
        m << "node '" << net.node_names[i] << "': power_schedule_W time " << entry.first
          << " s is not within the orbit period " << P << " s";
        throw InvalidInput(m.str());
      }
}

// Value of a schedule over the step ending at t (left limit, t <= 0 read as P).
double value_before(const std::vector<std::pair<double, double>>& s, double t, double P) {
  if (t <= 0.0) t = P;
  double w = s.back().second;
  for (const auto& [ts, ws] : s)
    if (ts < t) w = ws;
  return w;
}

}  // namespace

bool has_power_schedules(const ThermalNetwork& net) {
  for (const auto& s : net.power_schedule_W)
    if (!s.empty()) return true;
  return false;
}

Eigen::MatrixXd scheduled_power_W(const ThermalNetwork& net, const Eigen::VectorXd& times_s, double P) {
  check_times(net, P);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(net.num_nodes(), times_s.size());
  for (std::size_t i = 0; i < net.power_schedule_W.size(); ++i) {
    const auto& s = net.power_schedule_W[i];
    if (s.empty()) continue;
    for (Eigen::Index c = 0; c < times_s.size(); ++c) out(static_cast<Eigen::Index>(i), c) = value_before(s, times_s[c], P);
  }
  return out;
}

Eigen::VectorXd scheduled_power_mean_W(const ThermalNetwork& net, double P) {
  check_times(net, P);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(net.num_nodes());
  for (std::size_t i = 0; i < net.power_schedule_W.size(); ++i) {
    const auto& s = net.power_schedule_W[i];
    double energy_J = 0.0;
    for (std::size_t k = 0; k < s.size(); ++k) energy_J += s[k].second * ((k + 1 < s.size() ? s[k + 1].first : P) - s[k].first);
    out[static_cast<Eigen::Index>(i)] = energy_J / P;
  }
  return out;
}

Eigen::VectorXd power_switch_times_s(const ThermalNetwork& net, double P) {
  check_times(net, P);
  std::vector<double> t;
  for (const auto& s : net.power_schedule_W)
    for (std::size_t k = 0; k < s.size(); ++k) {
      // A change at k (from the previous entry, or from the last one at t = 0, which is the
      // orbit's start and already a step boundary).
      const double before = k > 0 ? s[k - 1].second : s.back().second;
      if (s[k].first > 0.0 && s[k].second != before) t.push_back(s[k].first);
    }
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return Eigen::Map<const Eigen::VectorXd>(t.data(), static_cast<Eigen::Index>(t.size()));
}

}  // namespace thermodec
