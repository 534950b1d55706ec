#pragma once
// Private to core/src/environment: the per-ray records that reduction trials reuse, and the
// tracer that writes and reads them.
//
// A reference run (LoadSamples) keeps, per ray family (the shadow rays of each sun direction,
// the Earth cone or hemisphere rays), one bit per ray (blocked by the spacecraft or not) and
// the distance [m] to the closest blocker of each blocked ray (RayRecords). A trial (LoadReuse)
// re-traces only the rays whose path up to that blocker (or to infinity) can enter the changed
// region (ChangeBox: a float box with a rounding margin, optionally the changed faces
// themselves); the others keep the recorded outcome. The tests are conservative, so a trial's
// loads equal a full run's bit for bit; memory is capped by
// ExternalLoadSettings::ray_record_budget_bytes.
#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "load_sides.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/rays/embree_scene.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::load_rays {

// The changed region of a trial as the ray tests see it: a float box grown by a margin that
// covers the slab test's rounding, so "does not enter" is never wrong.
// With `exact` (a scene of just the removed and added faces), a ray that enters the box is
// still clear if it meets none of those faces up to (just past) t_stop (`clear`). A ray that
// is traced if it is not clear (SideTracer) skips the exact test in small candidates
// (`clear_before_tracing`, tracing::exact_change_test_pays): there an occlusion query in the
// whole scene costs about what the exact one does.
struct ChangeBox {
  bool nothing = true;  // nothing changed: every recorded ray is reusable
  Eigen::AlignedBox3f box;
  float margin = 0.0f;
  const RayScene::Impl* exact = nullptr;
  bool exact_before_tracing = false;
  ChangeBox() = default;
  ChangeBox(const Eigen::AlignedBox3d& b, const RayScene* changed_faces, int candidate_faces) {
    if (changed_faces) exact = &changed_faces->impl();
    exact_before_tracing = tracing::exact_change_test_pays(candidate_faces);
    if (b.isEmpty()) return;
    nothing = false;
    const double scale = std::max({b.min().cwiseAbs().maxCoeff(), b.max().cwiseAbs().maxCoeff(), b.diagonal().norm()});
    margin = float(1e-4 * scale + 1e-9);
    box = Eigen::AlignedBox3f(b.min().cast<float>() - Eigen::Vector3f::Constant(margin),
                              b.max().cast<float>() + Eigen::Vector3f::Constant(margin));
  }
  // True if the ray o + t d (unit d) stays out of the region for t in [0, t_stop] (t_stop =
  // +inf: the whole half-line, NaN: only if it never enters).
  // How far along the ray the region counts: up to just past its blocker (+inf for an
  // escaped ray, NaN if the blocker's distance is unknown).
  float reach(float t_stop) const { return t_stop * (1.0f + 1e-4f) + margin; }
  bool clear_of_box(const float* o, const float* d, float t_stop) const {
    const float inv_d[3] = {1.0f / d[0], 1.0f / d[1], 1.0f / d[2]};
    return clear_of_box_inv(o, inv_d, t_stop);
  }
  // The same, `inv_d` = 1 / d per component.
  bool clear_of_box_inv(const float* o, const float* inv_d, float t_stop) const {
    if (nothing) return true;
    const float lo[3] = {box.min().x(), box.min().y(), box.min().z()};
    const float hi[3] = {box.max().x(), box.max().y(), box.max().z()};
    return !tracing::segment_may_enter_inv(o, inv_d, lo, hi, reach(t_stop));
  }
  bool clear_before_tracing(const float* o, const float* d, float t_stop) const {
    return exact_before_tracing ? clear(o, d, t_stop) : clear_of_box(o, d, t_stop);
  }
  bool clear(const float* o, const float* d, float t_stop) const {
    if (clear_of_box(o, d, t_stop)) return true;
    const float r = reach(t_stop);
    // note: an added face cannot unblock a ray and a removed one cannot block it, so "meets
    // no changed face before its blocker" is exact for both; NaN (blocker distance unknown)
    // stays "not clear".
    return exact && !std::isnan(r) && !tracing::segment_meets(*exact, o, d, r);
  }
};

// Per-ray results of one side's rays, and the reference record to reuse them from.
struct SideRays {
  std::vector<std::uint8_t> blocked;  // per ray
  // per ray: closest blocker [m] (recorded runs), +inf if open; in a Recorder's kept copy,
  // per blocked ray only (what pack_records keeps)
  std::vector<float> hit_m;
  std::vector<std::uint32_t> sample_index;  // Earth cone rays, recorded runs: see RayRecords
  std::vector<std::uint8_t> cell;
  std::vector<float> cos_theta;
  std::vector<float> origin_direction;  // Earth cone rays, recorded runs: 6 floats a ray
};

// One side's rays in a reference record, read in ray order.
struct RecordCursor {
  const RayRecords* rec = nullptr;
  std::int64_t ray0 = 0, count = 0, hit = 0;
  RecordCursor() = default;
  RecordCursor(const RayRecords* r, int side) {
    if (!r || r->empty() || side < 0) return;
    rec = r;
    ray0 = r->ray_begin[side];
    count = r->ray_begin[side + 1] - ray0;
    hit = r->hit_begin[side];
  }
  bool bit(std::int64_t i) const { return (rec->blocked[(ray0 + i) >> 6] >> ((ray0 + i) & 63)) & 1u; }
};

// Traces rays of one side at a time in chunks through Embree's stream API (rtcOccluded1M),
// appending each ray's blocked flag (and, when recording, its closest blocker's distance,
// from rtcIntersect1M on the blocked ones) to `out` in the order the rays were added. With a
// reference record, ray i < the record's count keeps the recorded result when its path up to
// the recorded blocker (or to infinity) does not enter the changed region: what it met there
// is unchanged and nothing new lies on it.
// Always incoherent (one ray at a time), also for the sun's parallel rays that Embree's packet
// traversal would fit: a packet decides a grazing ray with the other rays in it, and a trial
// traces only some of a side's rays again, in other packets than a full run's (measured: one
// sun ray of 2 278 on the sample, 4.6 mW; LoadReuse test a_grazing_shadow_ray...). Each ray's
// outcome must not depend on its neighbours.
class SideTracer {
 public:
  SideTracer(const RayScene& scene, bool record, const ChangeBox* change)
      : scene_(scene.impl().scene), record_(record), change_(change) {
    rtcInitIntersectContext(&ctx_);
    ctx_.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  }
  void begin(SideRays* out, RecordCursor ref = {}) {
    counted_ = 0;
    out_ = out;
    out_->blocked.clear();
    out_->hit_m.clear();
    out_->sample_index.clear();
    out_->cell.clear();
    out_->cos_theta.clear();
    out_->origin_direction.clear();
    ref_ = ref;
    next_ref_ = 0;
  }
  void add(const float* o, const float* d) {
    const std::size_t i = out_->blocked.size();
    if (static_cast<std::int64_t>(i) < ref_.count) {
      const bool b = ref_.bit(next_ref_++);
      const float t = b ? ref_.rec->hit_m[ref_.hit++] : kInf;
      if (change_->clear_before_tracing(o, d, t)) {
        keep_reference(b, t);
        return;
      }
    }
    out_->blocked.push_back(0);
    if (record_) out_->hit_m.push_back(kInf);
    index_[n_] = static_cast<int>(i);
    queue(o, d);
    if (n_ == kChunk) flush();
  }
  // The next ray keeps its reference outcome without being looked at (a conservative test
  // said it cannot reach the change); false if the record has no such ray (add() it instead).
  bool add_reused() {
    if (static_cast<std::int64_t>(out_->blocked.size()) >= ref_.count) return false;
    const bool b = ref_.bit(next_ref_++);
    keep_reference(b, b ? ref_.rec->hit_m[ref_.hit++] : kInf);
    return true;
  }
  // A ray known to be unblocked without tracing (a conservative geometric test said so).
  void add_open() {
    if (static_cast<std::int64_t>(out_->blocked.size()) < ref_.count && ref_.bit(next_ref_++)) ++ref_.hit;
    out_->blocked.push_back(0);
    if (record_) out_->hit_m.push_back(kInf);
  }
  void flush() {
    if (n_ == 0) return;
    traced += n_;
    rtcOccluded1M(scene_, &ctx_, buf_, static_cast<unsigned>(n_), sizeof(RTCRay));
    int m = 0;
    for (int k = 0; k < n_; ++k) {
      if (!(buf_[k].tfar < 0.0f)) continue;  // Embree sets tfar = -inf on occlusion
      out_->blocked[index_[k]] = 1;
      if (!record_) continue;
      RTCRayHit& h = hits_[m];
      h.ray = buf_[k];
      h.ray.tfar = kInf;
      h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      h.hit.primID = RTC_INVALID_GEOMETRY_ID;
      hit_index_[m++] = index_[k];
    }
    if (m > 0) {
      rtcIntersect1M(scene_, &ctx_, hits_, static_cast<unsigned>(m), sizeof(RTCRayHit));
      for (int k = 0; k < m; ++k)
        out_->hit_m[hit_index_[k]] =
            hits_[k].hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::quiet_NaN() : hits_[k].ray.tfar;
    }
    n_ = 0;
  }
  // A pass that keeps no per-ray outcome (not recording; the sun's): how many of the rays
  // from points[from..to) along the one direction `d` are open. Each ray is decided as add()
  // decides it (the reference outcome where its path cannot meet the change, else traced), in
  // the order given, continuing the side's earlier count_open calls; nothing is written to
  // `out`. The slab test's 1 / d is computed once for all of them.
  int count_open(const std::array<float, 3>* points, int from, int to, const float* d) {
    const float inv_d[3] = {1.0f / d[0], 1.0f / d[1], 1.0f / d[2]};
    int open = 0;
    for (int k = from; k < to; ++k, ++counted_) {
      const float* o = points[k].data();
      if (counted_ < ref_.count) {
        const bool b = ref_.bit(next_ref_++);
        const float t = b ? ref_.rec->hit_m[ref_.hit++] : kInf;
        if (change_->clear_of_box_inv(o, inv_d, t) || (change_->exact_before_tracing && change_->clear(o, d, t))) {
          open += !b;
          ++reused;
          continue;
        }
      }
      queue(o, d);
      if (n_ == kChunk) open += flush_count();
    }
    return open + flush_count();
  }
  long reused = 0, traced = 0;

 private:
  // Appends the ray o + t d, t in [0, inf), to the chunk to trace.
  void queue(const float* o, const float* d) {
    RTCRay& r = buf_[n_++];
    r.org_x = o[0]; r.org_y = o[1]; r.org_z = o[2];
    r.dir_x = d[0]; r.dir_y = d[1]; r.dir_z = d[2];
    r.tnear = 0.0f;
    r.tfar = kInf;
    r.time = 0.0f; r.mask = 0xFFFFFFFFu; r.id = 0; r.flags = 0;
  }
  // Traces the queued rays of count_open; how many are open.
  int flush_count() {
    if (n_ == 0) return 0;
    traced += n_;
    rtcOccluded1M(scene_, &ctx_, buf_, static_cast<unsigned>(n_), sizeof(RTCRay));
    int open = 0;
    for (int k = 0; k < n_; ++k) open += !(buf_[k].tfar < 0.0f);  // Embree sets tfar = -inf on occlusion
    n_ = 0;
    return open;
  }
  // The next ray's outcome is the reference's: blocked flag and blocker distance `t` [m].
  void keep_reference(bool b, float t) {
    out_->blocked.push_back(b);
    if (record_) out_->hit_m.insert(out_->hit_m.end(), 1, t);  // (push_back: gcc 12's false -Wdangling-pointer)
    ++reused;
  }
  RTCScene scene_;
  RTCIntersectContext ctx_;
  bool record_;
  const ChangeBox* change_;
  SideRays* out_ = nullptr;
  RecordCursor ref_;
  std::int64_t next_ref_ = 0, counted_ = 0;
  int n_ = 0;
  alignas(16) RTCRay buf_[kChunk];
  alignas(16) RTCRayHit hits_[kChunk];
  int index_[kChunk], hit_index_[kChunk];
};

// Per-side results of a recorded pass, packed into a RayRecords once the pass is done. The
// budget is shared by all passes of a run: once exceeded, recording stops for good.
struct Recorder {
  std::size_t budget = 0;
  std::atomic<std::size_t> used{0};
  std::atomic<bool> over{false};
  // Earth rays' origins and directions: a budget of their own; once exceeded, none are kept
  // (the rest of the record stays).
  std::size_t geometry_budget = 0;
  std::atomic<std::size_t> geometry_used{0};
  std::atomic<bool> geometry_over{false};
  bool active() const { return !over.load(std::memory_order_relaxed); }
  // Keeps side s's rays for packing, if the budget allows.
  void keep(std::vector<SideRays>& per_side, int s, SideRays& rays) {
    if (!active()) return;
    long blocked = 0;
    for (auto b : rays.blocked) blocked += b;
    const std::size_t bytes = rays.blocked.size() / 8 + 8 + 4 * blocked + 16 + 9 * rays.sample_index.size();
    if (used.fetch_add(bytes) + bytes > budget) {
      over = true;
      return;
    }
    per_side[s].blocked = rays.blocked;
    per_side[s].hit_m.clear();
    per_side[s].hit_m.reserve(blocked);
    for (std::size_t k = 0; k < rays.blocked.size(); ++k)
      if (rays.blocked[k]) per_side[s].hit_m.push_back(rays.hit_m[k]);
    per_side[s].sample_index = rays.sample_index;
    per_side[s].cell = rays.cell;
    per_side[s].cos_theta = rays.cos_theta;
    const std::size_t geometry_bytes = 4 * rays.origin_direction.size();
    if (geometry_bytes > 0 && !geometry_over.load(std::memory_order_relaxed)) {
      if (geometry_used.fetch_add(geometry_bytes) + geometry_bytes > geometry_budget)
        geometry_over = true;
      else
        per_side[s].origin_direction = rays.origin_direction;
    }
  }
};

//! Packs the per-side results of a recorded pass into one RayRecords (see its layout).
RayRecords pack_records(const std::vector<SideRays>& per_side);

// What a ray pass needs besides the geometry: reuse of a reference run (per side: index of
// the side in the reference's records, -1 = trace all) and recording.
struct PassContext {
  const ChangeBox* change = nullptr;
  const RayRecords* ref_records = nullptr;  // nullptr: no per-ray reuse
  const std::vector<int>* ref_side = nullptr;
  std::vector<SideRays>* record = nullptr;  // per side, filled if recording
  Recorder* recorder = nullptr;
  std::atomic<long>* reused_rays = nullptr;
  std::atomic<long>* traced_rays = nullptr;
  RecordCursor cursor(int s) const {
    return ref_records && ref_side ? RecordCursor(ref_records, (*ref_side)[s]) : RecordCursor();
  }
  bool recording() const { return record && recorder && recorder->active(); }
  void count(const SideTracer& t) const {
    if (reused_rays) *reused_rays += t.reused;
    if (traced_rays) *traced_rays += t.traced;
  }
};

}  // namespace thermodec::load_rays
