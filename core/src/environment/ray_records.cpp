// Packing of the per-ray records that trials reuse (ray_records.h).
#include "ray_records.h"

namespace thermodec::load_rays {

RayRecords pack_records(const std::vector<SideRays>& per_side) {
  RayRecords r;
  const int ns = static_cast<int>(per_side.size());
  r.ray_begin.assign(ns + 1, 0);
  r.hit_begin.assign(ns + 1, 0);
  for (int s = 0; s < ns; ++s) {
    long blocked = 0;
    for (auto b : per_side[s].blocked) blocked += b;
    r.ray_begin[s + 1] = r.ray_begin[s] + static_cast<std::int64_t>(per_side[s].blocked.size());
    r.hit_begin[s + 1] = r.hit_begin[s] + blocked;
  }
  r.blocked.assign((r.ray_begin[ns] + 63) / 64, 0);
  r.hit_m.resize(r.hit_begin[ns]);
  // Sample indices and cells only if every side has them (Earth cone rays).
  bool indexed = ns > 0;
  for (int s = 0; s < ns && indexed; ++s)
    indexed = per_side[s].sample_index.size() == per_side[s].blocked.size() &&
              per_side[s].cell.size() == per_side[s].blocked.size() &&
              per_side[s].cos_theta.size() == per_side[s].blocked.size();
  if (indexed) {
    r.sample_index.reserve(r.ray_begin[ns]);
    r.cell.reserve(r.ray_begin[ns]);
    r.cos_theta.reserve(r.ray_begin[ns]);
    for (int s = 0; s < ns; ++s) {
      r.sample_index.insert(r.sample_index.end(), per_side[s].sample_index.begin(), per_side[s].sample_index.end());
      r.cell.insert(r.cell.end(), per_side[s].cell.begin(), per_side[s].cell.end());
      r.cos_theta.insert(r.cos_theta.end(), per_side[s].cos_theta.begin(), per_side[s].cos_theta.end());
    }
  }
  // Origins and directions likewise, only if every side kept them.
  bool with_geometry = indexed;
  for (int s = 0; s < ns && with_geometry; ++s)
    with_geometry = per_side[s].origin_direction.size() == 6 * per_side[s].blocked.size();
  if (with_geometry) {
    r.origin_direction.reserve(6 * r.ray_begin[ns]);
    for (int s = 0; s < ns; ++s)
      r.origin_direction.insert(r.origin_direction.end(), per_side[s].origin_direction.begin(),
                                per_side[s].origin_direction.end());
  }
  for (int s = 0; s < ns; ++s) {
    std::int64_t bit = r.ray_begin[s], hit = r.hit_begin[s];
    std::size_t j = 0;  // (the kept copy's hit_m holds the blocked rays' distances only)
    for (std::size_t k = 0; k < per_side[s].blocked.size(); ++k, ++bit)
      if (per_side[s].blocked[k]) {
        r.blocked[bit >> 6] |= std::uint64_t(1) << (bit & 63);
        r.hit_m[hit++] = per_side[s].hit_m[j++];
      }
  }
  return r;
}

}  // namespace thermodec::load_rays
