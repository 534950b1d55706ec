#pragma once
//! The machine's memory, for budgets with a sane default.

namespace thermodec {

//! Physical memory of this machine (sysconf pages x page size) [bytes]; 0 where the system
//! does not tell.
long long physical_memory_bytes();

}  // namespace thermodec
