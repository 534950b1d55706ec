#pragma once
//! thermodec's version and the schema versions of the JSON files it writes. A schema version
//! changes when a key is renamed or removed or its meaning changes (added keys keep it).

namespace thermodec {

//! thermodec's release (also `thermodec --version`).
inline constexpr const char* kThermodecVersion = "0.1.0";
//! `thermodec simulate --json` result files (thermal/result_json.h).
inline constexpr int kResultSchemaVersion = 1;
//! `thermodec reduce` report.json (report/reduction_report.h).
inline constexpr int kReportSchemaVersion = 1;
//! `thermodec info --json` and `viewfactors --json` outputs.
inline constexpr int kInfoSchemaVersion = 1;

}  // namespace thermodec
