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

struct RecordBudget {
  std::size_t ir_bytes = 0;              //!< IR ray records (prepare_radiation)
  std::size_t load_bytes = 0;            //!< sun/Earth ray records (ExternalLoadSettings)
  std::size_t earth_geometry_bytes = 0;  //!< Earth cone ray origins and directions
};

//! The budget used when none is given [bytes]: 4.25 GiB, or a quarter of the machine's
//! physical memory if that is less (a laptop keeps room for the mesh, the solver and the OS).
std::size_t default_record_budget_bytes();

//! `total_bytes` shared 7 : 8 : 2 between IR, load and Earth-geometry records (the split
//! that the NASA meshes needed: 1.75 / 2 / 0.5 GiB of the default 4.25 GiB).
RecordBudget split_record_budget(std::size_t total_bytes);

}  // namespace thermodec
