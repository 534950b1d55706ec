#pragma once
// Private to core/src/radiation: what a RadiationReference keeps of its rays (RadiationReference::
// Impl) and the compact codes a candidate reads them through: octahedral directions, origin
// weights, direction cells and their cones; and the side matching between a reference and a
// candidate by face identity. Shared by prepare_radiation (radiation_reference.cpp) and
// radiative_couplings_incremental (incremental_couplings.cpp).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "thermodec/radiation/radiation_reference.h"
#include "thermodec/rays/tracing.h"

namespace thermodec {

struct RadiationReference::Impl {
  ThermalModel model;
  RadiationSettings settings;
  RayScene scene;
  FaceViewFactors vf;
  GebhartFactors gebhart;
  NodeCouplings couplings;
  std::unordered_map<std::uint64_t, int> side_of_key;
  // All reference rays' hits, empty if over budget. Side s owns [record_begin[s],
  // record_begin[s + 1]) of records, record_dir and ray_order, its rays grouped by direction
  // cell (kCells octahedral cells) and in ray order within a cell: position record_begin[s] + k
  // holds ray ray_order[record_begin[s] + k], cell c owning positions [cell_begin[s * (kCells + 1)
  // + c], cell_begin[s * (kCells + 1) + c + 1]) relative to record_begin[s]. In cell order, not
  // ray order, so that a candidate streams through the cells it looks at (in ray order, the
  // record reads of a cell's rays were scattered cache misses, the top stall of its ray loop).
  std::vector<tracing::RayRecord> records;
  std::vector<std::int64_t> record_begin;
  std::vector<std::uint32_t> record_dir;    // each recorded ray's direction, octahedral 2 x 16 bits
  // Each recorded ray's origin on its face: barycentric weights (w1, w2) of edges e1, e2,
  // 16 bits each (kOriginStep), so that a candidate places a ray without hashing its sample.
  std::vector<std::uint32_t> record_origin;
  std::vector<std::uint32_t> ray_order;
  std::vector<std::int32_t> cell_begin;
  std::size_t record_bytes_needed = 0;      // what the records above take when kept
  tracing::PrimTable prims;                 // hit classification in the reference scene
  std::vector<char> coincident_side;        // per side: in a coincident group (tracing.h)
  Impl(const ThermalModel& m, const RadiationSettings& s) : model(m), settings(s), scene(m.mesh) {}
};

namespace detail {

// Bytes a recorded ray takes: its record, direction, origin and place in cell order.
constexpr std::size_t kRecordBytesPerRay = sizeof(tracing::RayRecord) + 3 * sizeof(std::uint32_t);

// Barycentric weights in [0, 1] <-> 2 x 16 bits, to within kOriginStep / 2 each.
constexpr float kOriginStep = 1.0f / 65535.0f;
inline std::uint32_t origin_encode(float w1, float w2) {
  auto q = [](float w) { return static_cast<std::uint32_t>(std::lround(std::clamp(w, 0.0f, 1.0f) * 65535.0f)); };
  return q(w1) | (q(w2) << 16);
}
// Above this many changed faces, a side's rays are tested against the box of all of them
// instead of the box of those it can reach (a loop over them per side).
constexpr std::size_t kMaxRefinedFaces = 4096;
constexpr int kCellBits = 4, kCellsPerAxis = 1 << kCellBits, kCells = kCellsPerAxis * kCellsPerAxis;
// Direction cell of an octahedral code: the top kCellBits bits of each coordinate.
inline int oct_cell(std::uint32_t code) {
  return static_cast<int>(((code & 0xFFFFu) >> (16 - kCellBits)) | ((code >> (32 - kCellBits)) << kCellBits));
}

// Unit direction <-> 2 x 16-bit octahedral code (Cigolle et al., JCGT 2014). The decoded
// direction is within kOctAngle [rad] of the original (the grid step is 3e-5; generous bound).
constexpr float kOctAngle = 1e-3f;

//! Unit direction `d` -> 2 x 16-bit octahedral code.
std::uint32_t oct_encode(const float* d);

// note: multiplications by reciprocals, not divisions (a candidate decodes ~1e6 codes per
// trial); the result moves by an ulp or so, far inside kOctAngle.
inline void oct_decode(std::uint32_t code, float* d) {
  constexpr float kScale = 2.0f / 65535.0f;
  float u = float(code & 0xFFFFu) * kScale - 1.0f, v = float(code >> 16) * kScale - 1.0f;
  const float z = 1.0f - std::abs(u) - std::abs(v);
  if (z < 0.0f) {
    const float pu = (1.0f - std::abs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    const float pv = (1.0f - std::abs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
    u = pu;
    v = pv;
  }
  const float inv = 1.0f / std::sqrt(u * u + v * v + z * z);
  d[0] = u * inv;
  d[1] = v * inv;
  d[2] = z * inv;
}

// Per direction cell: centre direction and an angular radius [rad] covering every direction
// whose code falls in the cell (its boundary sampled finely, plus a margin for the bulge of
// the octahedral map between samples and for the code's own error).
struct CellCone {
  Eigen::Vector3f axis;
  float radius;  // [rad]
  float cos_r, sin_r;
};
//! The cones of all kCells cells (computed once per process).
const std::array<CellCone, kCells>& cell_cones();

// A sphere (centre, radius) as seen from the rays leaving an apex sphere: direction and the
// angle it can take up. seen_from(cone): can a ray from the apex sphere with a direction in
// the cell's cone meet it, i.e. angle(axis, to target) <= cone radius + asin(reach / dist)
// (conservative: + 1e-4 rad for float rounding).
struct ConeTarget {
  Eigen::Vector3f dir = Eigen::Vector3f::Zero();
  float spread = 0.0f;  // asin(reach / dist) [rad]
  float cos_s = 1.0f, sin_s = 0.0f;  // of spread + 1e-4
  bool inside = true;   // the apex sphere touches the target: every direction can meet it
  ConeTarget() = default;
  ConeTarget(const Eigen::Vector3f& apex, float apex_radius, const Eigen::Vector3f& centre, float radius) {
    const Eigen::Vector3f to = centre - apex;
    const float dist = to.norm(), reach = apex_radius + radius;
    inside = dist <= reach;
    if (inside) return;
    dir = to / dist;
    spread = std::asin(std::min(1.0f, reach / dist));
    cos_s = std::cos(spread + 1e-4f);
    sin_s = std::sin(spread + 1e-4f);
  }
  // angle(axis, dir) <= R = radius + spread + 1e-4 as dir . axis >= cos R, cos R by the angle
  // sum (no acos per test: a side tests every cell against up to 64 targets); R >= pi: always.
  bool seen_from(const CellCone& cone) const {
    if (inside || cone.radius + spread + 1e-4f >= 3.14159f) return true;
    const float cos_r = cone.cos_r * cos_s - cone.sin_r * sin_s;
    return cone.axis.dot(dir) >= cos_r - 1e-6f;
  }
};

//! The faces flagged in `in_a` (of `a`) and in `in_b` (of `b`), as one triangle soup (same float
//! coordinates as their own scenes, so Embree computes the same hits on them).
Mesh changed_faces(const Mesh& a, const std::vector<char>& in_a, const Mesh& b, const std::vector<char>& in_b);

// Twins by identity: same vertex coordinates, side and sidedness => same geometry
// (geo_twin); with the same ray count too => same rays (twin). A side of a node whose face
// count changed emits a different number of rays: traced afresh, but it is still the same
// surface for the rays of other sides that hit it. The changed geometry: candidate faces with
// a side new to the reference (added_face) and reference faces with a side gone from the
// candidate (removed_face), and their box.
struct SideMatch {
  std::vector<int> twin, geo_twin, cand_of_ref;
  std::vector<char> added_face, removed_face;
  Eigen::AlignedBox3d changed_box;
  int changed_sides = 0, reused_sides = 0, removed_sides = 0;
};
SideMatch match_sides(const RadiationReference::Impl& ref, const ThermalModel& candidate, const SurfaceSides& sides,
                      const Eigen::VectorXi& rays);

}  // namespace detail
}  // namespace thermodec
