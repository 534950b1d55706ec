#pragma once
//! Internal power over the orbit: the constant part (ThermalNetwork::power_W) plus the nodes'
//! piecewise-constant schedules (Node::power_schedule_W), periodic with the orbit period P.
//! Thermostat heaters are switched by the transient solver itself (thermal/transient.h).
#include <Eigen/Core>

#include "thermodec/thermal/network.h"

namespace thermodec {

//! Whether any node has a schedule.
bool has_power_schedules(const ThermalNetwork& network);

//! Scheduled power, N x K [W], at `times_s` (in [0, P]) as the value over the step that ends
//! there (left limit; t = 0 as the end of the orbit, P), as orbit_transient applies the loads.
//! Nodes without a schedule get 0 (their power is ThermalNetwork::power_W).
//! \throw InvalidInput if a schedule time is >= period_s or period_s <= 0.
Eigen::MatrixXd scheduled_power_W(const ThermalNetwork& network, const Eigen::VectorXd& times_s, double period_s);

//! Orbit mean of the scheduled power, N [W] (exact: sum of value x duration / P).
//! \throw as scheduled_power_W.
Eigen::VectorXd scheduled_power_mean_W(const ThermalNetwork& network, double period_s);

//! The instants in (0, P) where some schedule changes value, sorted, without duplicates: the
//! transient puts solver step boundaries there. \throw as scheduled_power_W.
Eigen::VectorXd power_switch_times_s(const ThermalNetwork& network, double period_s);

}  // namespace thermodec
