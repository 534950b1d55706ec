#pragma once
//! Peak resident memory of the running process, for reports and benchmarks.

namespace thermodec {

//! The largest resident set this process has had so far (getrusage ru_maxrss) [bytes];
//! 0 where the system does not tell.
long long peak_resident_memory_bytes();

}  // namespace thermodec
