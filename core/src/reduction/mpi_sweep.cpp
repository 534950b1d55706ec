#include "thermodec/reduction/mpi_sweep.h"

#include <mpi.h>

#include <cstdlib>
#include <exception>

#include "thermodec/common/errors.h"
#include "thermodec/common/peak_memory.h"
#include "thermodec/reduction/sweep_partition.h"

namespace thermodec {

namespace {
bool g_started = false;

// One rank's curves as doubles (node, sample count, stalled ratio, ratios, differences, faces,
// then per sample the difference field as rows, columns, values): NaN differences and face
// counts (< 2^53) travel exactly.
std::vector<double> pack(const std::vector<SensitivityCurve>& curves, int trials, long long peak_bytes) {
  std::vector<double> b{static_cast<double>(trials), static_cast<double>(peak_bytes)};
  for (const auto& c : curves) {
    b.push_back(c.node);
    b.push_back(static_cast<double>(c.ratios.size()));
    b.push_back(c.stalled_ratio);
    b.insert(b.end(), c.ratios.begin(), c.ratios.end());
    b.insert(b.end(), c.max_abs_dT_K.begin(), c.max_abs_dT_K.end());
    for (int f : c.faces_after) b.push_back(f);
    for (std::size_t i = 0; i < c.ratios.size(); ++i) {
      const Eigen::MatrixXd& d = i < c.dT_K.size() ? c.dT_K[i] : Eigen::MatrixXd();
      b.push_back(static_cast<double>(d.rows()));
      b.push_back(static_cast<double>(d.cols()));
      b.insert(b.end(), d.data(), d.data() + d.size());
    }
  }
  return b;
}

// Unpacks one rank's buffer [begin, end) into curves_by_node; returns its trial count.
int unpack(const double* p, const double* end, std::vector<SensitivityCurve>& curves_by_node, long long& peak) {
  const int trials = static_cast<int>(p[0]);
  peak = std::max(peak, static_cast<long long>(p[1]));
  for (p += 2; p < end;) {
    const int node = static_cast<int>(p[0]);
    const std::size_t m = static_cast<std::size_t>(p[1]);
    if (node < 0 || node >= static_cast<int>(curves_by_node.size()) || curves_by_node[node].node >= 0 || p + 3 + 3 * m > end)
      throw SolverError("internal: malformed sensitivity curves gathered from an MPI rank");
    SensitivityCurve& c = curves_by_node[node];
    c.node = node;
    c.stalled_ratio = p[2];
    p += 3;
    c.ratios.assign(p, p + m);
    c.max_abs_dT_K.assign(p + m, p + 2 * m);
    for (std::size_t i = 0; i < m; ++i) c.faces_after.push_back(static_cast<int>(p[2 * m + i]));
    p += 3 * m;
    for (std::size_t i = 0; i < m; ++i) {
      if (p + 2 > end) throw SolverError("internal: malformed sensitivity curves gathered from an MPI rank");
      const auto rows = static_cast<Eigen::Index>(p[0]), cols = static_cast<Eigen::Index>(p[1]);
      if (rows < 0 || cols < 0 || p + 2 + rows * cols > end)
        throw SolverError("internal: malformed sensitivity curves gathered from an MPI rank");
      c.dT_K.push_back(Eigen::Map<const Eigen::MatrixXd>(p + 2, rows, cols));
      p += 2 + rows * cols;
    }
  }
  return trials;
}
}  // namespace

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

MpiWorld start_mpi() {
  MpiWorld w;
  if (!launched_by_mpi()) return w;
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
      throw SolverError("MPI_Init_thread failed");
    g_started = true;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  return w;
}

void finish_mpi() {
  if (!g_started) return;
  g_started = false;
  MPI_Finalize();
}

SensitivitySweep mpi_sweep(const MpiWorld& world) {
  return [world](int num_nodes, const TrialFunction& trial, const SensitivityOptions& options,
                 const Eigen::VectorXi& faces_per_node, const std::function<int()>& trials_so_far) {
    const std::vector<int> owner = assign_nodes_to_processes(faces_per_node, world.size);
    std::vector<int> mine;
    for (int k = 0; k < num_nodes; ++k)
      if (owner[k] == world.rank) mine.push_back(k);
    const int trials_before = trials_so_far ? trials_so_far() : 0;
    std::vector<SensitivityCurve> local;
    std::exception_ptr failure;
    try {
      // note: an empty node list means "all nodes" to sensitivity_analysis.
      if (!mine.empty()) local = sensitivity_analysis(num_nodes, trial, options, mine);
    } catch (...) {
      failure = std::current_exception();
    }
    // Every rank learns whether any failed, so that none waits for curves that never come.
    int failed = failure ? 1 : 0, any_failed = 0;
    MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (failure) std::rethrow_exception(failure);
    if (any_failed) throw SolverError("the sensitivity sweep failed on another MPI rank (its message is on its stderr)");

    const int trials = (trials_so_far ? trials_so_far() : 0) - trials_before;
    const std::vector<double> buf = pack(local, trials, peak_resident_memory_bytes());
    int count = static_cast<int>(buf.size());
    std::vector<int> counts(world.size), offsets(world.size);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<double> all;
    if (world.rank == 0) {
      long long total = 0;
      for (int r = 0; r < world.size; ++r) {
        offsets[r] = static_cast<int>(total);
        total += counts[r];
      }
      all.resize(static_cast<std::size_t>(total));
    }
    MPI_Gatherv(buf.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0,
                MPI_COMM_WORLD);
    SweepOutcome out;
    if (world.rank != 0) {
      out.stop_after_sweep = true;
      return out;
    }
    std::vector<SensitivityCurve> by_node(num_nodes);
    for (int r = 0; r < world.size; ++r) {
      long long peak = 0;
      const int t = unpack(all.data() + offsets[r], all.data() + offsets[r] + counts[r], by_node, peak);
      if (r == 0) continue;  // rank 0's own trials and memory are counted by reduce_model / the front end
      out.trials_elsewhere += t;
      out.peak_memory_bytes_elsewhere = std::max(out.peak_memory_bytes_elsewhere, peak);
    }
    for (int k = 0; k < num_nodes; ++k)
      if (by_node[k].node != k) throw SolverError("internal: node " + std::to_string(k) + " was swept by no MPI rank");
    out.curves = std::move(by_node);
    return out;
  };
}

}  // namespace thermodec
