// Candidate couplings from a reference's rays (radiative_couplings_incremental).
//
// A candidate of the reduction driver differs from the reference in one or a few nodes. Its
// sides are matched to the reference's by identity (reference_records.h); a new or changed
// side traces all its rays, an unchanged one keeps its reference hit counts and re-traces only
// the rays that can meet the changed geometry before their reference hit: a box test per side
// (refined to the changed faces it can reach), then per direction cell, then per recorded ray
// (decoded origin and direction, widened by their code errors), then an exact segment test
// against a scene of the changed faces. Every test is conservative, so the view factors equal
// a full recompute's bit for bit; the Gebhart solve is warm-started from the reference's.
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

#include "reference_records.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/tracing.h"
#include "view_factor_rows.h"

namespace thermodec {
namespace {

using namespace detail;

// A box [m] in float, padded by `pad` [m].
Eigen::AlignedBox3f padded_box(const Eigen::AlignedBox3d& b, double pad) {
  return Eigen::AlignedBox3f((b.min().array() - pad).cast<float>().matrix(), (b.max().array() + pad).cast<float>().matrix());
}

// What every side's update reads: the reference, the candidate and the change between them.
struct Incremental {
  const RadiationReference::Impl& ref;
  const RadiationSettings& settings;
  const ThermalModel& candidate;
  const SurfaceSides& sides;
  const Eigen::VectorXi& rays;
  const std::vector<int>& twin;         // per candidate side: its reference twin with the same rays, or -1
  const std::vector<int>& cand_of_ref;  // per reference side: its candidate twin, or -1
  const Eigen::AlignedBox3d& changed_box;  // [m]
  const std::vector<std::array<Eigen::Vector3d, 3>>& changed_tris;  // the changed faces' corners [m]
  const Eigen::AlignedBox3f& box;  // changed_box padded, in float
  double pad;                      // its padding [m]
  const RayScene::Impl& changed;   // scene of the changed faces
  const RayScene& scene;           // the candidate's
  const tracing::PrimTable& prims;
  const std::vector<char>& ref_coincident;
  const std::vector<char>& cand_coincident;
  const tracing::SobolTable& sobol;
  bool records, exact_test;
  // Candidate side of reference side `ref_side` (-1: space; gone: the counter's bucket for
  // hits on faces that no longer exist).
  int to_cand(const tracing::Counter& cnt, int ref_side) const {
    return ref_side < 0 ? -1 : (cand_of_ref[ref_side] < 0 ? cnt.gone() : cand_of_ref[ref_side]);
  }
};

// Direction cells of a side whose rays can meet `sbox`, from the side's bounding sphere (centre
// `centre_d`, `radius` [m]): their rays' positions (relative to the side's first record) go to
// `subset`. `cb`: the side's cell offsets (RadiationReference::Impl::cell_begin).
void cells_toward_box(const std::int32_t* cb, const Eigen::Vector3d& centre_d, float radius,
                      const Eigen::AlignedBox3f& sbox, std::vector<std::uint32_t>& subset) {
  subset.clear();
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

// Box [m, float] of the changed faces the rays of the side emitted by `e` can reach, in `sbox`;
// false if none.
bool side_box(const Incremental& x, const sampling::Emitter& e, Eigen::AlignedBox3f& sbox) {
  const Eigen::AlignedBox3f& box = x.box;
  const bool records = x.records;
  const auto& changed_tris = x.changed_tris;
  const Eigen::AlignedBox3d& changed_box = x.changed_box;
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
  sbox = box;
  bool reaches = box_in_front;
  if (box_in_front && records && changed_tris.size() <= kMaxRefinedFaces) {
    const double travel = (e.a - changed_box.center()).norm() + 0.5 * changed_box.diagonal().norm() +
                          e.e1.norm() + e.e2.norm();
    const double slack = 1e-6 * (travel + e.a.cwiseAbs().maxCoeff() + changed_box.max().cwiseAbs().maxCoeff() +
                                 changed_box.min().cwiseAbs().maxCoeff());
    const double lim = 0.5 * e.offset - slack;
    Eigen::AlignedBox3d seen;
    for (const auto& tri : changed_tris)
      if ((tri[0] - e.a).dot(e.n) > lim || (tri[1] - e.a).dot(e.n) > lim || (tri[2] - e.a).dot(e.n) > lim)
        for (const auto& v : tri) seen.extend(v);
    reaches = !seen.isEmpty();
    if (reaches) sbox = padded_box(seen, x.pad);
  }
  return reaches;
}

// An unchanged side r (reference) with recorded rays: its rays that may reach `sbox` before
// their reference hit are traced in the candidate, the others keep their reference hit.
void retrace_recorded(const Incremental& x, const sampling::Emitter& e, int r, const Eigen::AlignedBox3f& sbox,
                      tracing::Counter& cnt, std::int64_t& back, std::int64_t& traced,
                      std::vector<std::uint32_t>& subset) {
  const RadiationReference::Impl& ref = x.ref;
  const tracing::PrimTable& prims = x.prims;
  const tracing::SobolTable& sobol = x.sobol;
  const RayScene& scene = x.scene;
  const RayScene::Impl& changed = x.changed;
  const bool exact_test = x.exact_test;
  const std::vector<char>& ref_coincident = x.ref_coincident;
  const std::vector<char>& cand_coincident = x.cand_coincident;
  const std::vector<int>& cand_of_ref = x.cand_of_ref;
  auto to_cand = [&](int ref_side) { return x.to_cand(cnt, ref_side); };
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
  cells_toward_box(cb, centre_d, radius, sbox, subset);
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
}

// An unchanged side without records: every ray meeting the changed faces is traced in the
// reference scene (its hit subtracted) and in the candidate (its hit added).
void retrace_both_scenes(const Incremental& x, const sampling::Emitter& e, int R, tracing::Counter& cnt,
                         std::int64_t& back, std::int64_t& traced) {
  const RadiationReference::Impl& ref = x.ref;
  const tracing::PrimTable& prims = x.prims;
  const tracing::SobolTable& sobol = x.sobol;
  const RayScene& scene = x.scene;
  const RayScene::Impl& changed = x.changed;
  const Eigen::AlignedBox3f& box = x.box;
  auto to_cand = [&](int ref_side) { return x.to_cand(cnt, ref_side); };
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

// True if every reference hit of side `r` is on a side the candidate keeps. A side whose rays
// cannot meet the change has no hit on a removed face; this checks it, so that a filter's miss
// takes the counted path below (and its safety net) rather than a silent copy.
bool hits_only_kept_sides(const Incremental& x, int r) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& F = x.ref.vf.F;
  for (int e = F.outerIndexPtr()[r]; e < F.outerIndexPtr()[r + 1]; ++e)
    if (x.cand_of_ref[F.innerIndexPtr()[e]] < 0) return false;
  return true;
}

// Candidate side c's hit counts into `rows`: traced whole if new or changed, else its
// reference counts corrected for the rays that can meet the change.
void update_side(const Incremental& x, int c, tracing::Counter& cnt, std::vector<std::uint32_t>& subset,
                 detail::SideRows& rows, std::int64_t& traced, std::atomic<int>& traced_whole) {
  const RadiationReference::Impl& ref = x.ref;
  const tracing::PrimTable& prims = x.prims;
  const tracing::SobolTable& sobol = x.sobol;
  const RayScene& scene = x.scene;
  const RadiationSettings& settings = x.settings;
  const ThermalModel& candidate = x.candidate;
  const SurfaceSides& sides = x.sides;
  const Eigen::VectorXi& rays = x.rays;
  const std::vector<int>& twin = x.twin;
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
    return;
  }
  // Unchanged face: the reference counts, corrected for the rays that can meet the changed
  // region: minus their reference hit, plus their candidate hit.
  Eigen::AlignedBox3f sbox;
  const bool reaches = side_box(x, e, sbox);
  if (!reaches && hits_only_kept_sides(x, r)) {  // the reference row as it is, copied at assembly
    rows.keep_reference(c, r);
    return;
  }
  auto to_cand = [&](int ref_side) { return x.to_cand(cnt, ref_side); };
  for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(ref.vf.F, r); it; ++it)
    cnt.add(to_cand(static_cast<int>(it.col())), static_cast<int>(std::lround(it.value() * R)));
  cnt.add(-1, static_cast<int>(std::lround(ref.vf.to_space[r] * R)));
  back = ref.vf.back_hits_per_side[r];
  if (reaches && x.records) {
    retrace_recorded(x, e, r, sbox, cnt, back, traced, subset);
  } else if (reaches) {
    retrace_both_scenes(x, e, R, cnt, back, traced);
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

}  // namespace

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
  if (!st.changed_box.isEmpty()) box = padded_box(st.changed_box, pad);

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
  const Incremental x{ref, settings, candidate, sides, rays, twin, cand_of_ref, st.changed_box, changed_tris, box,
                      pad, changed, scene, prims, ref_coincident, cand_coincident, sobol, records, exact_test};
  detail::SideRows rows(S);
  std::atomic<std::int64_t> retraced{0};
  std::atomic<int> traced_whole{0};
  tbb::enumerable_thread_specific<tracing::Counter> counters([S] { return tracing::Counter(S); });
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& range) {
    tracing::Counter& cnt = counters.local();
    std::vector<std::uint32_t> subset;
    std::int64_t traced = 0;
    for (int c = range.begin(); c != range.end(); ++c) update_side(x, c, cnt, subset, rows, traced, traced_whole);
    retraced.fetch_add(traced);
  });
  st.sides_traced_whole = traced_whole.load();
  st.rows_kept = static_cast<int>(std::count_if(rows.reference_row.begin(), rows.reference_row.end(), [](int r) { return r >= 0; }));
  const detail::ReferenceRows kept{ref.vf, cand_of_ref};
  FaceViewFactors vf = detail::assemble(sides, rows, settings.rays_per_face, rays, &kept);
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
