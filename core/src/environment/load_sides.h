#pragma once
// Private to core/src/environment: the face sides as the load rays see them (corners, normal,
// area [m^2], ray-origin lift [m], single-precision copies for the ray generation), their
// scrambling seeds and sample points. Shared by the direct sun (direct_sun.h), the Earth rays
// (earth_cone.h, escaping_rays.h) and the per-ray records (ray_records.h).
//
// Sampling: the ray stage's Owen-scrambled Sobol points (rays/sampling.h), scrambled per side
// from a hash of the seed and the side's identity, so loads get the view factors' variance
// properties and an unchanged face keeps its sample points in a modified model.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "thermodec/environment/orbit.h"
#include "thermodec/mesh/mesh.h"
#include "thermodec/rays/sampling.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec::load_rays {

constexpr double kPi = 3.14159265358979323846;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kChunk = 256;  // rays per Embree stream call: fits in L1 and amortises the call

struct Side {
  Eigen::Vector3d a, b, c, normal;
  double area = 0.0;
  double offset = 0.0;  // ray-origin lift along the normal [m]
  // Single precision for the ray generation (Embree traces in float anyway): the lifted
  // corner a + offset n, the edges b - a and c - a, the normal.
  float fa[3], fe1[3], fe2[3], fn[3];
};

// Scrambling seeds of a side for one purpose: a pure function of (seed, side identity), so
// an unchanged face keeps its sample points and rays in a modified model and results ignore
// thread count.
inline std::array<std::uint32_t, 4> side_seeds(std::uint64_t seed, std::uint64_t key, std::uint64_t purpose) {
  std::array<std::uint32_t, 4> out;
  const std::uint64_t h = sampling::hash_combine(sampling::hash_combine(key, seed), 0x10ad5000ull + purpose);
  for (int d = 0; d < 4; ++d) out[d] = std::uint32_t(sampling::hash_combine(h, d) >> 32);
  return out;
}

// Owen-scrambled coordinate in (0, 1] of a bit-reversed Sobol value (sampling::sobol_4d_reversed):
// owen_scramble(x, seed) = reverse_bits(laine_karras(reverse_bits(x), seed)), one reversal saved.
inline float scrambled(std::uint32_t reversed, std::uint32_t seed) {
  return sampling::to_unit_float(sampling::reverse_bits(sampling::laine_karras(reversed, seed))) + 0.5f / 16777216.0f;
}

// Area-preserving square -> triangle map (barycentric (1 - sqrt u, sqrt u (1 - v), sqrt u v)),
// lifted off the face: the ray origin.
inline void on_side(const Side& g, float u, float v, float* o) {
  const float su = std::sqrt(u), w1 = su * (1.0f - v), w2 = su * v;
  for (int k = 0; k < 3; ++k) o[k] = g.fa[k] + g.fe1[k] * w1 + g.fe2[k] * w2;
}

//! Geometry of every side of `sides` (faces of `mesh`); sides without area get area 0.
std::vector<Side> side_geometry(const Mesh& mesh, const SurfaceSides& sides);

inline void orthonormal_frame(const Eigen::Vector3d& n, Eigen::Vector3d& t, Eigen::Vector3d& u) {
  t = (std::abs(n.x()) > 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX()).cross(n).normalized();
  u = n.cross(t);
}

// Pilot size of a side drawing `rays` samples: at least `pilot_rays`, doubled until it is 1/32
// of the side's samples. What a pilot can miss (a shadow or a blocked view between all its
// points) is then worth at most ~32 of the side's samples, not 1/256 of a huge CAD panel (a
// 256-point pilot on Juno's 87 m^2 triangles caught a sliver shadow for some seeds only:
// 528 W seed to seed).
inline int pilot_count(int rays, int pilot_rays) {
  int p = std::max(1, pilot_rays);
  while (p < rays / 32) p *= 2;
  return std::max(1, std::min(rays, p));
}

}  // namespace thermodec::load_rays
