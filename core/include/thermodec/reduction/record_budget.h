#pragma once
//! Memory for the reference's reusable ray records, the part of a reduction's memory that
//! grows with rays rather than faces. Trials reuse the records to re-trace only rays that can
//! meet a change; without them every ray near the change is traced again, with the same
//! results, slower. Sizes per record: IR ray 20 bytes (first hit, compressed direction and
//! origin, direction-cell slot: radiation_reference.h); sun or Earth ray 1 bit, plus 4 bytes
//! if blocked and 9 bytes for an Earth ray (environment/external_loads.h, RayRecords); Earth
//! cone ray geometry 24 bytes.
#include <cstddef>

namespace thermodec {

//! One pool for the IR and the sun/Earth records, filled by need in the order they are made:
//! the IR records first (their size is known before tracing: 20 bytes a ray), up to
//! `ir_max_bytes`; the sun/Earth records then get what the IR records left of `records_bytes`.
//! The Earth cone ray geometry has a budget of its own.
struct RecordBudget {
  std::size_t records_bytes = 0;         //!< IR and sun/Earth records together
  std::size_t ir_max_bytes = 0;          //!< IR records at most (prepare_radiation)
  std::size_t earth_geometry_bytes = 0;  //!< Earth cone ray origins and directions

  //! The sun/Earth records' budget (ExternalLoadSettings) once the IR records took `ir_kept_bytes`.
  std::size_t load_bytes(std::size_t ir_kept_bytes) const {
    return ir_kept_bytes < records_bytes ? records_bytes - ir_kept_bytes : 0;
  }
};

//! The budget used when none is given [bytes]: 4.25 GiB, or a quarter of the machine's
//! physical memory if that is less (a laptop keeps room for the mesh, the solver and the OS).
std::size_t default_record_budget_bytes();

//! `asked_bytes` (a --record-memory), or the default if it is 0.
inline std::size_t record_budget_bytes(std::size_t asked_bytes) {
  return asked_bytes > 0 ? asked_bytes : default_record_budget_bytes();
}

//! `total_bytes` split: 2/17 for the Earth ray geometry, the rest for the records, of which
//! the IR records may take up to 3/4 (the sun/Earth records keep at least 1/4). With the
//! default 4.25 GiB: Earth geometry 0.5 GiB, records 3.75 GiB, IR at most 2.81 GiB. The NASA
//! meshes' sun/Earth records take 0.4-0.5 GiB and their IR records 1.4-1.9 GiB (a fixed
//! 1.75 GiB IR share left Juno's out).
RecordBudget split_record_budget(std::size_t total_bytes);

}  // namespace thermodec
