#pragma once
//! Returning freed memory to the system between the large stages of a run.

namespace thermodec {

//! Hands the pages of freed heap blocks back to the system (glibc: malloc_trim), so that the
//! resident memory after a stage is what the stage kept, not what it once used. A reference's
//! tracing and load sampling free gigabytes of small per-side blocks (on a 31k-face model,
//! 1.4 GiB of the 2 GiB heap was free after the reference's loads), which the allocator
//! otherwise keeps while the next stage maps new memory beside them. No effect elsewhere.
void release_free_memory();

}  // namespace thermodec
