#pragma once
//! The sensitivity sweep spread over MPI ranks (built when CMake finds MPI, option
//! THERMODEC_WITH_MPI; defines THERMODEC_HAS_MPI for the code that uses it). Every rank builds
//! the same reference (deterministic), sweeps its share of the nodes
//! (assign_nodes_to_processes), and rank 0 gathers all curves in node order, runs the strategy
//! and writes the outputs: the result is the single-process one, bit for bit.
#include "thermodec/reduction/reduce_model.h"

namespace thermodec {

struct MpiWorld {
  int rank = 0;  //!< this process
  int size = 1;  //!< processes in MPI_COMM_WORLD (1: not under an MPI launcher)
};

//! Whether an MPI launcher started this process (mpirun / mpiexec of Open MPI, srun --mpi=pmix,
//! hydra): its environment says so (OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_RANK).
bool launched_by_mpi();

//! Starts MPI (MPI_Init_thread, funneled: only the calling thread talks MPI) when
//! launched_by_mpi(), else does nothing and returns {0, 1}. Call once, from the main thread.
MpiWorld start_mpi();

//! Ends MPI if start_mpi() started it (MPI_Finalize); no-op otherwise.
void finish_mpi();

//! ReduceSettings::sweep for `world`: this rank's share of the nodes, curves gathered to rank 0,
//! trial counts summed and the other ranks' peak memory maxed there; ranks other than 0 get
//! stop_after_sweep. A failure on any rank is raised on every rank (SolverError on the others).
SensitivitySweep mpi_sweep(const MpiWorld& world);

}  // namespace thermodec
