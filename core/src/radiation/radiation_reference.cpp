#include "thermodec/radiation/radiation_reference.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>

#include "thermodec/common/errors.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/tracing.h"
#include "view_factor_rows.h"

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
  tracing::PrimTable prims;                 // hit classification in the reference scene
  std::vector<char> coincident_side;        // per side: in a coincident group (tracing.h)
  Impl(const ThermalModel& m, const RadiationSettings& s) : model(m), settings(s), scene(m.mesh) {}
};

RadiationReference::RadiationReference(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RadiationReference::RadiationReference(RadiationReference&&) noexcept = default;
RadiationReference& RadiationReference::operator=(RadiationReference&&) noexcept = default;
RadiationReference::~RadiationReference() = default;
const ThermalModel& RadiationReference::model() const { return impl_->model; }
const RadiationSettings& RadiationReference::settings() const { return impl_->settings; }
const FaceViewFactors& RadiationReference::face_view_factors() const { return impl_->vf; }
const GebhartFactors& RadiationReference::gebhart() const { return impl_->gebhart; }
const NodeCouplings& RadiationReference::couplings() const { return impl_->couplings; }

namespace {
std::uint32_t oct_encode(const float* d);
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
}  // namespace

RadiationReference prepare_radiation(const ThermalModel& reference, const RadiationSettings& settings,
                                     std::size_t max_record_bytes) {
  auto impl = std::make_unique<RadiationReference::Impl>(reference, settings);
  const int N = static_cast<int>(reference.nodes.size());
  const SurfaceSides sides = surface_sides(impl->model);
  const Eigen::VectorXi rays = side_ray_counts(sides, settings);
  const bool keep = double(rays.cast<double>().sum()) * (sizeof(tracing::RayRecord) + 3 * sizeof(std::uint32_t)) <=
                    double(max_record_bytes);
  impl->vf = detail::trace_all(impl->scene, sides, settings, keep ? &impl->records : nullptr, &impl->record_begin);
  if (keep) {
    // Directions, compressed, so that a candidate can skip most rays without generating them.
    impl->record_dir.resize(impl->records.size());
    impl->record_origin.resize(impl->records.size());
    const auto sobol_table = tracing::shared_sobol_table(sides.size() ? rays.maxCoeff() : 0);
    const tracing::SobolTable& sobol = *sobol_table;
    tbb::parallel_for(tbb::blocked_range<int>(0, sides.size(), 8), [&](const tbb::blocked_range<int>& range) {
      for (int s = range.begin(); s != range.end(); ++s) {
        const sampling::Emitter e = tracing::side_emitter(impl->model.mesh, sides, s, settings.seed);
        std::uint32_t* out = impl->record_dir.data() + impl->record_begin[s];
        std::uint32_t* out_origin = impl->record_origin.data() + impl->record_begin[s];
        for (int i = 0; i < rays[s]; ++i) {
          float org[3], dir[3], w1, w2;
          sampling::emit(e, sobol[i], true, org, dir);
          sampling::origin_weights(e, sobol[i], w1, w2);
          out[i] = oct_encode(dir);
          out_origin[i] = origin_encode(w1, w2);
        }
      }
    });
    const int S = sides.size();
    impl->ray_order.resize(impl->records.size());
    impl->cell_begin.assign(std::size_t(S) * (kCells + 1), 0);
    tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& range) {
      std::vector<int> count(kCells);
      std::vector<tracing::RayRecord> rec;
      std::vector<std::uint32_t> dir;
      for (int s = range.begin(); s != range.end(); ++s) {
        const std::int64_t b = impl->record_begin[s];
        std::fill(count.begin(), count.end(), 0);
        for (int i = 0; i < rays[s]; ++i) ++count[oct_cell(impl->record_dir[b + i])];
        std::int32_t* cb = impl->cell_begin.data() + std::size_t(s) * (kCells + 1);
        for (int c = 0; c < kCells; ++c) cb[c + 1] = cb[c] + count[c];
        std::fill(count.begin(), count.end(), 0);
        for (int i = 0; i < rays[s]; ++i) {
          const int c = oct_cell(impl->record_dir[b + i]);
          impl->ray_order[b + cb[c] + count[c]++] = static_cast<std::uint32_t>(i);
        }
        // Records and directions from ray order into cell order.
        rec.assign(impl->records.begin() + b, impl->records.begin() + b + rays[s]);
        dir.assign(impl->record_dir.begin() + b, impl->record_dir.begin() + b + rays[s]);
        for (int k = 0; k < rays[s]; ++k) {
          impl->records[b + k] = rec[impl->ray_order[b + k]];
          impl->record_dir[b + k] = dir[impl->ray_order[b + k]];
        }
        dir.assign(impl->record_origin.begin() + b, impl->record_origin.begin() + b + rays[s]);
        for (int k = 0; k < rays[s]; ++k) impl->record_origin[b + k] = dir[impl->ray_order[b + k]];
      }
    });
  }
  const Eigen::VectorXd eps = side_emissivity(impl->model, sides);
  impl->gebhart = gebhart_factors(impl->vf, eps, node_groups(sides, N), N + 1);
  impl->couplings = aggregate_couplings(impl->vf, eps, impl->gebhart, N);
  impl->couplings.diagnostics.untraceable_faces = impl->scene.num_skipped_faces();
  for (int s = 0; s < sides.size(); ++s) impl->side_of_key.emplace(sides.key[s], s);
  impl->prims = tracing::prim_table(impl->scene.impl(), sides);
  impl->coincident_side = tracing::coincident_side_flags(impl->prims, sides.size());
  return RadiationReference(std::move(impl));
}

namespace {
// Unit direction <-> 2 x 16-bit octahedral code (Cigolle et al., JCGT 2014). The decoded
// direction is within kOctAngle [rad] of the original (the grid step is 3e-5; generous bound).
constexpr float kOctAngle = 1e-3f;

std::uint32_t oct_encode(const float* d) {
  const float l1 = std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]);
  float u = d[0] / l1, v = d[1] / l1;
  if (d[2] < 0.0f) {
    const float pu = (1.0f - std::abs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    const float pv = (1.0f - std::abs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
    u = pu;
    v = pv;
  }
  auto q = [](float x) { return static_cast<std::uint32_t>(std::lround((std::clamp(x, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); };
  return q(u) | (q(v) << 16);
}

// note: multiplications by reciprocals, not divisions (a candidate decodes ~1e6 codes per
// trial); the result moves by an ulp or so, far inside kOctAngle.
void oct_decode(std::uint32_t code, float* d) {
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
const std::array<CellCone, kCells>& cell_cones() {
  static const std::array<CellCone, kCells> cones = [] {
    std::array<CellCone, kCells> out;
    auto dir = [](double u, double v) {
      float d[3];
      const auto q = [](double x) { return static_cast<std::uint32_t>(std::lround(std::clamp(x, 0.0, 1.0) * 65535.0)); };
      oct_decode(q(u) | (q(v) << 16), d);
      return Eigen::Vector3f(d[0], d[1], d[2]);
    };
    const double w = 1.0 / kCellsPerAxis;
    for (int cv = 0; cv < kCellsPerAxis; ++cv)
      for (int cu = 0; cu < kCellsPerAxis; ++cu) {
        const double u0 = cu * w, v0 = cv * w;
        Eigen::Vector3f axis = dir(u0 + 0.5 * w, v0 + 0.5 * w);
        float worst = 1.0f;
        constexpr int kSamples = 64;
        for (int k = 0; k <= kSamples; ++k) {
          const double t = double(k) / kSamples;
          for (const auto& [u, v] : {std::pair{u0 + t * w, v0}, std::pair{u0 + t * w, v0 + w}, std::pair{u0, v0 + t * w},
                                     std::pair{u0 + w, v0 + t * w}})
            worst = std::min(worst, axis.dot(dir(u, v)));
        }
        const float radius = std::acos(std::clamp(worst, -1.0f, 1.0f)) * 1.1f + 0.02f;
        const float r = std::min(radius, 3.14159265f);
        out[cu + kCellsPerAxis * cv] = {axis, r, std::cos(r), std::sin(r)};
      }
    return out;
  }();
  return cones;
}

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

void extend_by_face(Eigen::AlignedBox3d& box, const Mesh& mesh, int f) {
  for (int k = 0; k < 3; ++k) box.extend(Eigen::Vector3d(mesh.V.row(mesh.F(f, k))));
}

// The faces flagged in `a` and in `b`, as one triangle soup (same float coordinates as their
// own scenes, so Embree computes the same hits on them).
Mesh changed_faces(const Mesh& a, const std::vector<char>& in_a, const Mesh& b, const std::vector<char>& in_b) {
  const auto count = [](const std::vector<char>& v) { return static_cast<int>(std::count(v.begin(), v.end(), 1)); };
  const int n = count(in_a) + count(in_b);
  Mesh m;
  m.V.resize(3 * n, 3);
  m.F.resize(n, 3);
  m.face_node = Eigen::VectorXi::Zero(n);
  m.face_material = Eigen::VectorXi::Constant(n, -1);
  m.face_back_material = Eigen::VectorXi::Constant(n, -1);
  int k = 0;
  for (const auto& [mesh, flag] : {std::pair<const Mesh*, const std::vector<char>*>{&a, &in_a}, {&b, &in_b}})
    for (int f = 0; f < mesh->num_faces(); ++f)
      if ((*flag)[f]) {
        for (int j = 0; j < 3; ++j) {
          m.V.row(3 * k + j) = mesh->V.row(mesh->F(f, j));
          m.F(k, j) = 3 * k + j;
        }
        ++k;
      }
  return m;
}

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
                      const Eigen::VectorXi& rays) {
  const int S = sides.size(), Sr = ref.vf.sides.size();
  const Eigen::VectorXi& ref_rays = ref.vf.side_rays;
  SideMatch m;
  m.twin.assign(S, -1);
  m.geo_twin.assign(S, -1);
  m.cand_of_ref.assign(Sr, -1);
  for (int c = 0; c < S; ++c) {
    const auto it = ref.side_of_key.find(sides.key[c]);
    if (it != ref.side_of_key.end() && m.cand_of_ref[it->second] < 0) {
      m.geo_twin[c] = it->second;
      m.cand_of_ref[it->second] = c;
      if (ref_rays[it->second] == rays[c]) m.twin[c] = it->second;
    }
  }
  m.added_face.assign(candidate.mesh.num_faces(), 0);
  m.removed_face.assign(ref.model.mesh.num_faces(), 0);
  for (int c = 0; c < S; ++c) {
    (m.twin[c] < 0 ? m.changed_sides : m.reused_sides) += 1;
    if (m.geo_twin[c] < 0 && !m.added_face[sides.face[c]]) {
      m.added_face[sides.face[c]] = 1;
      extend_by_face(m.changed_box, candidate.mesh, sides.face[c]);
    }
  }
  for (int r = 0; r < Sr; ++r)
    if (m.cand_of_ref[r] < 0) {
      ++m.removed_sides;
      if (!m.removed_face[ref.vf.sides.face[r]]) {
        m.removed_face[ref.vf.sides.face[r]] = 1;
        extend_by_face(m.changed_box, ref.model.mesh, ref.vf.sides.face[r]);
      }
    }
  return m;
}

}  // namespace

GeometryChange geometry_change(const RadiationReference& reference, const ThermalModel& candidate) {
  const RadiationReference::Impl& ref = reference.impl();
  const SurfaceSides sides = surface_sides(candidate);
  const SideMatch m = match_sides(ref, candidate, sides, side_ray_counts(sides, ref.settings));
  GeometryChange change;
  change.box = m.changed_box;
  change.faces = changed_faces(ref.model.mesh, m.removed_face, candidate.mesh, m.added_face);
  return change;
}

NodeCouplings radiative_couplings_incremental(const RadiationReference& reference, const ThermalModel& candidate,
                                              IncrementalStats* stats, FaceViewFactors* face_vf,
                                              const RayScene* candidate_scene) {
  const RadiationReference::Impl& ref = reference.impl();
  const RadiationSettings& settings = ref.settings;
  const int N = static_cast<int>(candidate.nodes.size());
  const SurfaceSides sides = surface_sides(candidate);
  const int S = sides.size();
  const Eigen::VectorXi rays = side_ray_counts(sides, settings);

  const SideMatch match = match_sides(ref, candidate, sides, rays);
  const std::vector<int>&twin = match.twin, &cand_of_ref = match.cand_of_ref;
  IncrementalStats st;
  st.changed_sides = match.changed_sides;
  st.reused_sides = match.reused_sides;
  st.removed_sides = match.removed_sides;
  st.changed_box = match.changed_box;
  const std::vector<char>&added_face = match.added_face, &removed_face = match.removed_face;
  Mesh changed_mesh = changed_faces(ref.model.mesh, removed_face, candidate.mesh, added_face);
  const RayScene changed_scene(changed_mesh);
  // Their corners, for the per-side test of which of them a side's rays can reach at all.
  std::vector<std::array<Eigen::Vector3d, 3>> changed_tris(changed_mesh.num_faces());
  for (int f = 0; f < changed_mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) changed_tris[f][k] = changed_mesh.V.row(changed_mesh.F(f, k)).transpose();
  if (stats) st.changed_faces = std::move(changed_mesh);  // (the scene keeps its own copy)
  st.rays_total = rays.cast<std::int64_t>().sum();
  // The filter box in float, padded by far more than the rounding of float coordinates, so a
  // ray that reaches a changed face can never be judged to miss the box.
  Eigen::AlignedBox3f box;
  const double pad = st.changed_box.isEmpty() ? 0.0 : 1e-4 * (st.changed_box.sizes().norm() + st.changed_box.min().cwiseAbs().maxCoeff() +
                                                               st.changed_box.max().cwiseAbs().maxCoeff());
  auto padded = [pad](const Eigen::AlignedBox3d& b) {
    return Eigen::AlignedBox3f((b.min().array() - pad).cast<float>().matrix(), (b.max().array() + pad).cast<float>().matrix());
  };
  if (!st.changed_box.isEmpty()) box = padded(st.changed_box);

  const RayScene::Impl& changed = changed_scene.impl();
  std::optional<RayScene> own_scene;
  if (!candidate_scene) own_scene.emplace(candidate.mesh);
  const RayScene& scene = candidate_scene ? *candidate_scene : *own_scene;
  const tracing::PrimTable prims = tracing::prim_table(scene.impl(), sides);
  // Sides of faces that overlap another face in one plane (coincident_faces.h), in the
  // reference and in the candidate. A hit on such a group is resolved by the tie rule among
  // members whose own intersections may lie a little past the hit (their planes agree to the
  // grouping tolerance, ~1e-6 x the scene's size; far more than the exact test's margin for a
  // grazing ray): a ray whose reference hit is on one is traced, not tested (on Juno an
  // exact test passed over a removed member and the ray kept its hit on it).
  const std::vector<char>& ref_coincident = ref.coincident_side;
  const std::vector<char> cand_coincident = tracing::coincident_side_flags(prims, S);
  const auto sobol_table = tracing::shared_sobol_table(S ? rays.maxCoeff() : 0);
  const tracing::SobolTable& sobol = *sobol_table;
  const bool records = !ref.records.empty();
  const bool exact_test = tracing::exact_change_test_pays(candidate.mesh.num_faces());
  detail::SideRows rows(S);
  std::atomic<std::int64_t> retraced{0};
  std::atomic<int> traced_whole{0};
  tbb::enumerable_thread_specific<tracing::Counter> counters([S] { return tracing::Counter(S); });
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& range) {
    tracing::Counter& cnt = counters.local();
    std::vector<std::uint32_t> subset;
    std::int64_t traced = 0;
    for (int c = range.begin(); c != range.end(); ++c) {
      const sampling::Emitter e = tracing::side_emitter(candidate.mesh, sides, c, settings.seed);
      std::int64_t back = 0;
      const int r = twin[c], R = rays[c];
      if (r < 0) {  // new or changed face: all its rays
        tracing::trace_emitter(scene.impl(), prims, e, sobol, R, tracing::AllRays{}, [&](int, int hit, bool b, float) {
          cnt.add(hit, 1);
          back += b;
        });
        traced += R;
        if (rows.take(c, cnt, back) != 0) traced_whole.fetch_add(1);
        continue;
      }
      // Unchanged face: the reference counts, corrected for the rays that can meet the changed
      // region: minus their reference hit, plus their candidate hit.
      auto to_cand = [&](int ref_side) {
        return ref_side < 0 ? -1 : (cand_of_ref[ref_side] < 0 ? cnt.gone() : cand_of_ref[ref_side]);
      };
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(ref.vf.F, r); it; ++it)
        cnt.add(to_cand(static_cast<int>(it.col())), static_cast<int>(std::lround(it.value() * R)));
      cnt.add(-1, static_cast<int>(std::lround(ref.vf.to_space[r] * R)));
      back = ref.vf.back_hits_per_side[r];
      // Every point a ray of this side reaches lies strictly in front of its plane: if the
      // whole box is behind it, no ray can meet it.
      bool box_in_front = false;
      if (!box.isEmpty())
        for (int k = 0; k < 8 && !box_in_front; ++k)
          box_in_front = (box.corner(Eigen::AlignedBox3f::CornerType(k)).cast<double>() - e.a).dot(e.n) > 0.0;
      // The changed faces this side's rays can reach: those with a corner above half its
      // origin lift. Its rays start a full lift [m] above its plane and go up, short of float
      // rounding (direction ~1e-7, origin ~1e-7 x coordinates; `slack` allows ~10x that), so
      // the faces of a neighbouring panel sharing an edge or lying behind it are out of reach.
      // Their box (padded like the global one) bounds the side's ray tests below; none: the
      // side keeps its reference counts as they are. On the sample, most rays of a changed
      // node's neighbours were looked at for nothing because the box of all changed faces
      // reached in front of them.
      Eigen::AlignedBox3f sbox = box;
      bool reaches = box_in_front;
      if (box_in_front && records && changed_tris.size() <= kMaxRefinedFaces) {
        const double travel = (e.a - st.changed_box.center()).norm() + 0.5 * st.changed_box.diagonal().norm() +
                              e.e1.norm() + e.e2.norm();
        const double slack = 1e-6 * (travel + e.a.cwiseAbs().maxCoeff() + st.changed_box.max().cwiseAbs().maxCoeff() +
                                     st.changed_box.min().cwiseAbs().maxCoeff());
        const double lim = 0.5 * e.offset - slack;
        Eigen::AlignedBox3d seen;
        for (const auto& tri : changed_tris)
          if ((tri[0] - e.a).dot(e.n) > lim || (tri[1] - e.a).dot(e.n) > lim || (tri[2] - e.a).dot(e.n) > lim)
            for (const auto& v : tri) seen.extend(v);
        reaches = !seen.isEmpty();
        if (reaches) sbox = padded(seen);
      }
      if (reaches && records) {
        // A ray whose reference hit comes before it enters the box hits the same face in the
        // candidate (the faces in front of the box did not change, the new ones are inside).
        const tracing::RayRecord* rec = ref.records.data() + ref.record_begin[r];
        const Eigen::Vector3d sbox_centre = sbox.center().cast<double>();
        // No ray can enter the box before travelling the distance between the face's bounding
        // box (grown by the origin lift) and the changed box: a reference hit closer than
        // that is kept without even generating the ray.
        Eigen::AlignedBox3d face_box;
        face_box.extend(e.a).extend(Eigen::Vector3d(e.a + e.e1)).extend(Eigen::Vector3d(e.a + e.e2));
        const double lift = 2.0 * e.offset + 1e-6 * (face_box.max().cwiseAbs().maxCoeff() + 1.0);
        const Eigen::Vector3d gap = (sbox.min().cast<double>() - face_box.max()).cwiseMax(face_box.min() - sbox.max().cast<double>()).cwiseMax(0.0);
        const float reach = static_cast<float>(std::max(0.0, gap.norm() - lift) * (1.0 - 1e-5));
        // Every origin of this side lies within `radius` of the face box's centre; a ray longer
        // than `far` is past the box. A ray whose recorded origin and direction, widened by
        // their errors, cannot bring its segment into the box is kept without being generated.
        const Eigen::Vector3d centre_d = face_box.center();
        const float radius = static_cast<float>(0.5 * face_box.diagonal().norm() + lift);
        const float far = static_cast<float>((centre_d - sbox_centre).norm() +
                                             0.5 * sbox.diagonal().cast<double>().norm()) + radius;
        // From its recorded origin and direction, each within a known distance of the ray's:
        // the decoded direction within kOctAngle, so the point at distance l within
        // l kOctAngle; the origin within (|e1| + |e2|) kOriginStep / 2 (plus float rounding).
        const std::uint32_t* rdir = ref.record_dir.data() + ref.record_begin[r];
        const std::uint32_t* rorg = ref.record_origin.data() + ref.record_begin[r];
        const std::uint32_t* ray_of = ref.ray_order.data() + ref.record_begin[r];
        // (plus float rounding: of the origin's coordinates, and of the box entry along the ray)
        const float origin_pad = static_cast<float>((e.e1.norm() + e.e2.norm()) * kOriginStep +
                                                    1e-6 * (e.a.cwiseAbs().maxCoeff() + e.e1.norm() + e.e2.norm())) +
                                 1e-6f * far;
        const float smin[3] = {sbox.min().x(), sbox.min().y(), sbox.min().z()};
        const float smax[3] = {sbox.max().x(), sbox.max().y(), sbox.max().z()};
        auto may_enter = [&](int i) {
          float d[3], o[3];
          oct_decode(rdir[i], d);
          const float w1 = float(rorg[i] & 0xFFFFu) * kOriginStep, w2 = float(rorg[i] >> 16) * kOriginStep;
          for (int k = 0; k < 3; ++k) o[k] = e.fa[k] + e.fe1[k] * w1 + e.fe2[k] * w2;
          const float len = std::min(rec[i].t, far), pad = len * kOctAngle + origin_pad;
          const float lo[3] = {smin[0] - pad, smin[1] - pad, smin[2] - pad};
          const float hi[3] = {smax[0] + pad, smax[1] + pad, smax[2] + pad};
          return tracing::segment_may_enter(o, d, lo, hi, len);
        };
        // Only the direction cells whose cone, cast from the side's bounding sphere, can meet the
        // box hold rays worth looking at: first against the box's bounding sphere, then, for the
        // cells that pass, against the bounding spheres of up to 4 x 4 x 4 equal parts of it
        // (one of them must pass). The parts follow the box's shape: a flat panel's box is
        // split along its two long sides only, and its 16 parts' spheres leave out the cells
        // that only the whole box's sphere could see (those along the panel's plane).
        const std::int32_t* cb = ref.cell_begin.data() + std::size_t(r) * (kCells + 1);
        subset.clear();
        {
          const auto& cones = cell_cones();
          const Eigen::Vector3f apex = centre_d.cast<float>();
          const Eigen::Vector3f ext = sbox.sizes();
          const float longest = ext.maxCoeff();
          int parts[3];
          for (int k = 0; k < 3; ++k)
            parts[k] = longest > 0.0f ? std::clamp(static_cast<int>(std::ceil(4.0f * ext[k] / longest - 0.5f)), 1, 4) : 1;
          const Eigen::Vector3f step(ext.x() / parts[0], ext.y() / parts[1], ext.z() / parts[2]);
          // (plus float rounding of the parts' centres)
          const float part_r = 0.5f * step.norm() * (1.0f + 1e-5f) +
                               1e-6f * std::max(sbox.min().cwiseAbs().maxCoeff(), sbox.max().cwiseAbs().maxCoeff());
          std::array<ConeTarget, 64> part;
          int num_parts = 0;
          for (int i = 0; i < parts[0]; ++i)
            for (int j = 0; j < parts[1]; ++j)
              for (int k = 0; k < parts[2]; ++k) {
                const Eigen::Vector3f c = sbox.min() + step.cwiseProduct(Eigen::Vector3f(i + 0.5f, j + 0.5f, k + 0.5f));
                part[num_parts++] = ConeTarget(apex, radius, c, part_r);
              }
          const ConeTarget whole(apex, radius, sbox.center(), 0.5f * sbox.diagonal().norm());
          for (int cell = 0; cell < kCells; ++cell) {
            if (cb[cell + 1] == cb[cell]) continue;
            bool pass = whole.seen_from(cones[cell]);
            if (pass && num_parts > 1) {
              pass = false;
              for (int q = 0; q < num_parts && !pass; ++q) pass = part[q].seen_from(cones[cell]);
            }
            if (pass)
              for (std::int32_t k = cb[cell]; k < cb[cell + 1]; ++k) subset.push_back(static_cast<std::uint32_t>(k));
          }
        }
        tracing::trace_emitter(
            scene.impl(), prims, e, sobol, static_cast<int>(subset.size()),
            [&](int i, const float* o, const float* d) {
              const float entry = tracing::ray_box_entry(o, d, sbox);
              if (!(entry < std::numeric_limits<float>::infinity() && entry <= rec[i].t)) return false;
              // Exact test: a ray that meets no removed or added face up to (just past) its
              // reference hit keeps that hit (every face it could reach first is unchanged).
              // Without it the ray is traced: same hit if unchanged, counted -1 +1.
              const int hit = rec[i].side();
              if (!exact_test || (hit >= 0 && (ref_coincident[hit] || (cand_of_ref[hit] >= 0 && cand_coincident[cand_of_ref[hit]]))))
                return true;
              return tracing::segment_meets(changed, o, d, rec[i].t * (1.0f + 1e-5f));
            },
            [&](int i, int hit, bool b, float) {
              cnt.add(to_cand(rec[i].side()), -1);
              back -= rec[i].back();
              cnt.add(hit, 1);
              back += b;
              ++traced;
            },
            [&](int i) { return rec[i].t >= reach && may_enter(i); }, subset.data(), ray_of);
      } else if (reaches) {
        auto meets = [&](int, const float* o, const float* d) {
          return tracing::ray_box_entry(o, d, box) < std::numeric_limits<float>::infinity() &&
                 tracing::segment_meets(changed, o, d, std::numeric_limits<float>::infinity());
        };
        tracing::trace_emitter(ref.scene.impl(), ref.prims, e, sobol, R, meets, [&](int, int hit, bool b, float) {
          cnt.add(to_cand(hit), -1);
          back -= b;
          ++traced;
        });
        tracing::trace_emitter(scene.impl(), prims, e, sobol, R, meets, [&](int, int hit, bool b, float) {
          cnt.add(hit, 1);
          back += b;
          ++traced;
        });
      }
      if (rows.take(c, cnt, back) != 0) {
        // A ray kept its reference hit on a removed face: a filter above let it through. The
        // side is traced whole instead (what a full recompute counts), and the miss is counted
        // (IncrementalStats::sides_traced_whole; tests expect none).
        back = 0;
        tracing::trace_emitter(scene.impl(), prims, e, sobol, R, tracing::AllRays{}, [&](int, int hit, bool b, float) {
          cnt.add(hit, 1);
          back += b;
        });
        traced += R;
        rows.take(c, cnt, back);
        traced_whole.fetch_add(1);
      }
    }
    retraced.fetch_add(traced);
  });
  st.sides_traced_whole = traced_whole.load();
  FaceViewFactors vf = detail::assemble(sides, rows, settings.rays_per_face, rays);
  st.rays_retraced = retraced.load();
  vf.rays_traced = st.rays_retraced;

  const Eigen::VectorXd eps = side_emissivity(candidate, sides);
  // Warm start: unchanged sides start from their reference Gebhart row (same node columns).
  RowMatrixXd guess;
  const bool warm = static_cast<int>(ref.model.nodes.size()) == N;
  if (warm) {
    guess = RowMatrixXd::Zero(S, N + 2);
    for (int c = 0; c < S; ++c)
      if (twin[c] >= 0) guess.row(c) = ref.gebhart.B.row(twin[c]);
  }
  const GebhartFactors gb = gebhart_factors(vf, eps, node_groups(sides, N), N + 1, {}, warm ? &guess : nullptr);
  NodeCouplings nc = aggregate_couplings(vf, eps, gb, N);
  nc.diagnostics.untraceable_faces = scene.num_skipped_faces();
  if (stats) *stats = st;
  if (face_vf) *face_vf = std::move(vf);
  return nc;
}

}  // namespace thermodec
