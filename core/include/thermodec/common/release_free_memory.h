#pragma once
//! Freed heap memory: handed back to the system between the large stages of a run, or kept
//! for reuse in a process that runs one job.

namespace thermodec {

//! Hands the pages of freed heap blocks back to the system (glibc: malloc_trim), so that the
//! resident memory after a stage is what the stage kept, not what it once used. A reference's
//! tracing and load sampling free gigabytes of small per-side blocks (on a 31k-face model,
//! 1.4 GiB of the 2 GiB heap was free after the reference's loads), which the allocator
//! otherwise keeps while the next stage maps new memory beside them. No effect elsewhere.
void release_free_memory();

//! For a process that runs one thermodec job (the CLI; not a host such as MeshLab or FreeCAD,
//! whose allocator is theirs): freed blocks of every size stay in the heap for the next ones
//! (glibc: no separate mapping for large blocks, no automatic trimming of the heap's top).
//! A reduction's trials allocate and free the same large buffers (Gebhart rows and residuals,
//! Earth hits, candidate meshes) hundreds of times; each fresh mapping costs a page fault per
//! 4 KiB touched (Juno at 0.5 K: 7.0 M faults and 69 s of system time, 2.5 M and 33 s kept;
//! docs/benchmarks.md). release_free_memory() still hands free pages back between stages.
void keep_freed_memory_for_reuse();

}  // namespace thermodec
