// External loads: direct sun with self-shadowing, Earth albedo and IR through ray-traced
// face-to-Earth view factors, and solar-band diffuse reflections (Gebhart with absorptivity).
// The paper (Sec. III) lists the three effects that make a face's incident solar power:
// its angle to the source, occlusion by other faces, and reflections from other faces.
#include "thermodec/environment/external_loads.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_map>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"
// The ray stage's Owen-scrambled Sobol sampler: the same sequences and side seeding as the
// view factors, so loads get the same variance properties.
#include "thermodec/rays/sampling.h"
#include "thermodec/rays/embree_scene.h"
#include "thermodec/rays/tracing.h"
#include "sphere_tree.h"

namespace thermodec {
namespace {

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
std::array<std::uint32_t, 4> side_seeds(std::uint64_t seed, std::uint64_t key, std::uint64_t purpose) {
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

std::vector<Side> side_geometry(const Mesh& mesh, const SurfaceSides& sides) {
  std::vector<Side> out(sides.size());
  for (int s = 0; s < sides.size(); ++s) {
    const int f = sides.face[s];
    Side& g = out[s];
    g.a = mesh.V.row(mesh.F(f, 0)).transpose();
    g.b = mesh.V.row(mesh.F(f, 1)).transpose();
    g.c = mesh.V.row(mesh.F(f, 2)).transpose();
    const Eigen::Vector3d n = (g.b - g.a).cross(g.c - g.a);
    g.area = 0.5 * n.norm();
    g.normal = n.normalized();
    if (sides.is_back[s]) {
      g.normal = -g.normal;
      std::swap(g.b, g.c);  // keep the (a, b, c) winding counter-clockwise seen from this side
    }
    // note: like the view-factor rays, the lift depends on this face only (not on the scene
    // extent), so an unchanged face casts bit-identical rays in a decimated model.
    g.offset = 1e-5 * std::max({g.a.cwiseAbs().maxCoeff(), g.b.cwiseAbs().maxCoeff(), g.c.cwiseAbs().maxCoeff(),
                                (g.b - g.a).norm(), (g.c - g.a).norm()});
    const Eigen::Vector3d lifted = g.a + g.offset * g.normal, e1 = g.b - g.a, e2 = g.c - g.a;
    for (int k = 0; k < 3; ++k) {
      g.fa[k] = float(lifted[k]);
      g.fe1[k] = float(e1[k]);
      g.fe2[k] = float(e2[k]);
      g.fn[k] = float(g.normal[k]);
    }
  }
  return out;
}

void orthonormal_frame(const Eigen::Vector3d& n, Eigen::Vector3d& t, Eigen::Vector3d& u) {
  t = (std::abs(n.x()) > 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX()).cross(n).normalized();
  u = n.cross(t);
}

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
  std::vector<float> hit_m;           // per ray: closest blocker [m] (recorded runs), +inf if open
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
    per_side[s].hit_m = rays.hit_m;
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
    for (std::size_t k = 0; k < per_side[s].blocked.size(); ++k, ++bit)
      if (per_side[s].blocked[k]) {
        r.blocked[bit >> 6] |= std::uint64_t(1) << (bit & 63);
        r.hit_m[hit++] = per_side[s].hit_m[k];
      }
  }
  return r;
}

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

// True if no point of side t's triangle lies above side s's plane by more than half s's ray
// lift: rays leaving s (lifted by its offset, going away from its plane) can never meet t.
// Adjacent faces of one panel and faces behind s are ruled out so.
bool below_plane_of(const Side& s, const Side& t) {
  const double h = 0.5 * s.offset;
  return s.normal.dot(t.a - s.a) <= h && s.normal.dot(t.b - s.a) <= h && s.normal.dot(t.c - s.a) <= h;
}

// For the conservative "can anything block this side's rays" tests: per side, a bounding
// sphere (plus its ray lift and float rounding: Embree works in single precision), and a
// sphere tree over the faces that could block (each face once, whichever side). A face can
// block side s in some direction only if it is not below s's plane (below_plane_of).
// Direction-independent: built once per run.
struct Occluders {
  std::vector<Eigen::Vector3d> centre;
  std::vector<double> radius;  // < 0 for sides without area
  std::vector<int> face;       // per side: its face
  blockers::SphereTree tree;   // over one side per face
};

// Bounding sphere of a side's ray origins (its triangle lifted by up to its offset, with room
// for rounding): centre `c`, returns the radius [m].
double side_bounding_sphere(const Side& g, Eigen::Vector3d& c) {
  c = (g.a + g.b + g.c) / 3.0;
  return std::max({(g.a - c).norm(), (g.b - c).norm(), (g.c - c).norm()}) + 2.0 * g.offset +
         1e-6 * (c.cwiseAbs().maxCoeff() + g.offset) + 1e-9;
}

Occluders occluders(const std::vector<Side>& geo, const SurfaceSides& sides) {
  const int ns = sides.size();
  Occluders o;
  o.centre.assign(ns, Eigen::Vector3d::Zero());
  o.radius.assign(ns, -1.0);
  o.face.assign(sides.face.data(), sides.face.data() + ns);
  std::vector<int> blockers;  // one side per face
  for (int s = 0; s < ns; ++s) {
    const Side& g = geo[s];
    if (g.area <= 0.0) continue;
    o.radius[s] = side_bounding_sphere(g, o.centre[s]);
    const int f = sides.face[s];
    if (sides.front_side[f] < 0 || sides.front_side[f] == s) blockers.push_back(s);
  }
  o.tree = blockers::sphere_tree(blockers, o.centre, o.radius, [&](int t, int k) -> const Eigen::Vector3d& {
    return k == 0 ? geo[t].a : k == 1 ? geo[t].b : geo[t].c;
  });
  return o;
}

// True if some potential blocker t of side s (another face, not below s's plane) passes
// `meets(centre, reach)` with reach = radius(s) + radius(t); `meets` must be monotone in reach
// (a bigger sphere passes whenever a smaller one inside it does).
template <class Meets>
bool any_blocker(const std::vector<Side>& geo, const Occluders& occ, int s, Meets&& meets) {
  const Side& g = geo[s];
  const double h = 0.5 * g.offset;  // as below_plane_of
  const double slack = 1e-9 * (g.a.cwiseAbs().maxCoeff() + 1.0);
  return blockers::any_member(
      occ.tree,
      [&](const blockers::SphereTree::Node& n) {
        return blockers::height_above_plane(n, g.normal, g.a) > h - slack && meets(n.centre, occ.radius[s] + n.radius);
      },
      [&](int t) {
        return occ.face[t] != occ.face[s] && !below_plane_of(g, geo[t]) && meets(occ.centre[t], occ.radius[s] + occ.radius[t]);
      });
}

// Which sides facing `toward` (unit) may be shadowed at all: some potential blocker's bounding
// sphere meets the prism their rays sweep (the side's bounding sphere moved along `toward`).
// The others are lit whatever their sample points, exactly, and need no rays. Only the sides
// flagged in `todo` (all if null) are tested: a trial reuses the others whole (for the sample's
// 60 sun directions per trial, testing every side cost ~2 % of an incremental trial).
std::vector<char> may_be_shadowed(const std::vector<Side>& geo, const Occluders& occ, const Eigen::Vector3d& toward,
                                  const std::vector<char>* todo = nullptr) {
  const int ns = static_cast<int>(geo.size());
  std::vector<char> out(ns, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      const double facing = geo[s].normal.dot(toward);
      if (occ.radius[s] < 0.0 || facing <= 0.0 || (todo && !(*todo)[s])) continue;
      if (facing < 1e-6) {  // grazing: float rays could sink below the lift, let Embree decide
        out[s] = 1;
        continue;
      }
      // a blocker's sphere meets the prism the side's sphere sweeps along `toward`
      out[s] = any_blocker(geo, occ, s, [&](const Eigen::Vector3d& centre, double reach) {
        const Eigen::Vector3d v = centre - occ.centre[s];
        const double along = v.dot(toward);
        if (along < -reach) return false;  // wholly behind the rays' start
        return v.squaredNorm() - along * along <= reach * reach;
      });
    }
  });
  return out;
}

// Pilot size of a side drawing `rays` samples: at least `pilot_rays`, doubled until it is 1/32
// of the side's samples. What a pilot can miss (a shadow or a blocked view between all its
// points) is then worth at most ~32 of the side's samples, not 1/256 of a huge CAD panel (a
// 256-point pilot on Juno's 87 m^2 triangles caught a sliver shadow for some seeds only:
// 528 W seed to seed).
int pilot_count(int rays, int pilot_rays) {
  int p = std::max(1, pilot_rays);
  while (p < rays / 32) p *= 2;
  return std::max(1, std::min(rays, p));
}

// Unblocked fraction of each side's sample points towards the direction `toward` (unit),
// for sides facing it; 0 for the others. A pilot of the first P Sobol points (P a power of 2:
// one per 1/P-area stratum of the Owen-scrambled net) decides fully lit or fully shadowed
// sides; only sides where the pilot disagrees trace all `rays`. note: a shadow that slips
// between all P pilot points is missed; it then covers well under 1/P of the face (measured on
// the sample: P = 16 left 0.6 W seed-to-seed differences on single nodes, P = 64 < 0.2 W).
// `origins` (per side, filled on first use): the sample points, the same at every step.
Eigen::VectorXd sunlit_fraction(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                                const Eigen::Vector3d& toward, const Eigen::VectorXi& side_rays, int pilot_rays,
                                std::uint64_t seed, const tracing::SobolTable& sobol, const Occluders& occ,
                                const PassContext& pass, std::vector<std::vector<std::array<float, 3>>>& origins,
                                const std::vector<char>* todo = nullptr) {
  const int ns = sides.size();
  Eigen::VectorXd frac = Eigen::VectorXd::Zero(ns);
  const float dir[3] = {float(toward.x()), float(toward.y()), float(toward.z())};
  const bool recording = pass.recording();
  const std::vector<char> shadowable = may_be_shadowed(geo, occ, toward, todo);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 32), [&](const tbb::blocked_range<int>& range) {
    SideTracer tracer(scene, recording, pass.change);
    SideRays rays_out;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0 || g.normal.dot(toward) <= 0.0 || (todo && !(*todo)[s])) continue;
      if (!shadowable[s]) {  // exact: every sample point sees the sun
        frac[s] = 1.0;
        continue;
      }
      const int rays = side_rays[s], pilot = pilot_count(rays, pilot_rays);
      tracer.begin(&rays_out, pass.cursor(s));
      // Traces sample points from..to of the side's scrambled net; returns how many see the sun.
      auto trace = [&](const std::array<std::uint32_t, 4>& sd, int from, int to) {
        const std::size_t first = rays_out.blocked.size();
        auto& points = origins[s];  // (a side is one thread's at a step, and steps run in turn)
        for (int k = static_cast<int>(points.size()); k < to; ++k)
          on_side(g, scrambled(sobol[k][0], sd[0]), scrambled(sobol[k][1], sd[1]), points.emplace_back().data());
        if (!recording) return tracer.count_open(points.data(), from, to, dir);  // (outcomes not kept)
        for (int k = from; k < to; ++k) tracer.add(points[k].data(), dir);
        tracer.flush();
        int open = 0;
        for (std::size_t i = first; i < rays_out.blocked.size(); ++i) open += !rays_out.blocked[i];
        return open;
      };
      const auto sd = side_seeds(seed, sides.key[s], 1);
      const int open_pilot = trace(sd, 0, pilot);
      if (open_pilot == 0 || open_pilot == pilot || pilot == rays) {
        frac[s] = double(open_pilot) / pilot;
      } else {
        frac[s] = double(open_pilot + trace(sd, pilot, rays)) / rays;
      }
      if (recording) pass.recorder->keep(*pass.record, s, rays_out);
    }
    pass.count(tracer);
  });
  return frac;
}

// Earth rays of each side. Directions are drawn uniformly (stratified) inside the cone the
// Earth subtends, not over the hemisphere: every ray then lands on the Earth, the integrand
// (cos theta x visibility x albedo lighting) is smooth wherever the spacecraft does not block
// the view, and the estimate of an unobstructed side is nearly exact. Each ray keeps its
// weight Omega_cap / (pi N) max(0, n . w) (its share of F_side->Earth) and the Earth normal
// at its hit point (for the albedo lighting at every time step).
struct EarthHits {
  std::vector<std::vector<std::pair<float, Eigen::Vector3f>>> rays;  // per side: (weight, normal)
  Eigen::VectorXd view_factor;                                        // per side: sum of weights
  // per side: binomial relative standard error of view_factor, sqrt((1 - p) / (p N)) for an
  // unblocked share p of N rays (0 for unobstructed or fully blocked sides)
  Eigen::VectorXd relative_error;
  // per side: 1 if every ray it traced had its outcome read from the reference record (none
  // traced again): its rays, weights and normals are then the reference's.
  std::vector<char> replayed;
  // The same, flattened for the per-step albedo sums: columns (nx, ny, nz) and weights, side s
  // owning [begin[s], begin[s + 1]).
  Eigen::Matrix<float, Eigen::Dynamic, 3> normals;
  Eigen::VectorXf weights;
  std::vector<int> begin;

  void flatten() {
    begin.assign(rays.size() + 1, 0);
    for (size_t s = 0; s < rays.size(); ++s) begin[s + 1] = begin[s] + static_cast<int>(rays[s].size());
    normals.resize(begin.back(), 3);
    weights.resize(begin.back());
    for (size_t s = 0; s < rays.size(); ++s)
      for (size_t k = 0; k < rays[s].size(); ++k) {
        weights[begin[s] + k] = rays[s][k].first;
        normals.row(begin[s] + k) = rays[s][k].second.transpose();
      }
    rays.clear();
  }
  bool empty() const { return begin.empty(); }
};

// Which sides may have their view of the Earth blocked at all: some other face's bounding
// sphere meets the set of rays leaving the side's bounding sphere inside the Earth's cone
// and in front of the side. The pilot alone would call a side unobstructed when a small
// blocker slips between its pilot rays, a seed-dependent (heavy-tailed) error; with this
// conservative geometric test such sides always trace all their rays.
std::vector<char> may_be_blocked_from_earth(const std::vector<Side>& geo, const Occluders& occ,
                                            const Eigen::Vector3d& earth_dir, double sin_half,
                                            const std::vector<char>* todo) {
  const int ns = static_cast<int>(geo.size());
  const double cos_half = std::sqrt(1.0 - sin_half * sin_half);
  std::vector<char> out(ns, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      if (occ.radius[s] < 0.0 || (todo && !(*todo)[s])) continue;
      out[s] = any_blocker(geo, occ, s, [&](const Eigen::Vector3d& centre, double reach) {
        const Eigen::Vector3d v = centre - occ.centre[s];
        if (v.dot(geo[s].normal) < -reach) return false;  // wholly behind the side
        const double dist2 = v.squaredNorm();
        if (dist2 <= reach * reach) return true;
        // angle(v, earth) <= half + asin(reach / dist), compared through cosines (both angles
        // in [0, pi], cos decreasing there): cos(half + beta) = cos_half cos_beta - sin_half sin_beta.
        const double dist = std::sqrt(dist2), sin_b = reach / dist, cos_b = std::sqrt(1.0 - sin_b * sin_b);
        return v.dot(earth_dir) / dist >= cos_half * cos_b - sin_half * sin_b - 1e-6;  // (float ray directions)
      });
    }
  });
  return out;
}

// Earth cone direction cells: 16 x 16 cells of equal solid angle, rows by (1 - cos a) of the
// angle a to the Earth's centre, columns by azimuth; a ray's cell follows from its two
// direction coordinates (u_a, u_phi) in (0, 1].
constexpr int kEarthCellsPerAxis = 16, kEarthCells = kEarthCellsPerAxis * kEarthCellsPerAxis;
inline std::uint8_t earth_cell(float u_a, float u_phi) {
  const int i = std::min(kEarthCellsPerAxis - 1, static_cast<int>(u_a * kEarthCellsPerAxis));
  const int j = std::min(kEarthCellsPerAxis - 1, static_cast<int>(u_phi * kEarthCellsPerAxis));
  return static_cast<std::uint8_t>(i * kEarthCellsPerAxis + j);
}

// Centre direction of each cell and an angular radius bounding every direction of the cell
// (half its polar extent plus its azimuthal arc at its widest polar angle, with room for float
// rounding), as cosine and sine; for an Earth cone of half-angle acos(cos_half) about `axis`
// with the azimuth frame (t, u) the rays use.
struct EarthCellTable {
  std::array<Eigen::Vector3d, kEarthCells> dir;
  std::array<double, kEarthCells> cos_radius, sin_radius;
  EarthCellTable(const Eigen::Vector3d& axis, const Eigen::Vector3d& t, const Eigen::Vector3d& u, double cos_half) {
    for (int i = 0; i < kEarthCellsPerAxis; ++i) {
      const double a0 = std::acos(1.0 - (1.0 - cos_half) * i / kEarthCellsPerAxis);
      const double a1 = std::acos(1.0 - (1.0 - cos_half) * (i + 1) / kEarthCellsPerAxis), am = 0.5 * (a0 + a1);
      for (int j = 0; j < kEarthCellsPerAxis; ++j) {
        const double ph = 2.0 * kPi * (j + 0.5) / kEarthCellsPerAxis;
        const int c = i * kEarthCellsPerAxis + j;
        dir[c] = std::cos(am) * axis + std::sin(am) * (std::cos(ph) * t + std::sin(ph) * u);
        const double radius = 0.5 * (a1 - a0) + std::sin(a1) * kPi / kEarthCellsPerAxis + 1e-3;
        cos_radius[c] = std::cos(radius);
        sin_radius[c] = std::sin(radius);
      }
    }
  }
};

// One Earth cone ray of a side: origin [m] and unit direction (body axes), cosine to the side's
// normal, angle a to the Earth's centre (cos, sin), azimuth (cos, sin) and direction cell.
struct EarthRay {
  float o[3], d[3], cos_t, cos_a, sin_a, cp, sp;
  std::uint8_t cell;
};

// Which cells `box` can be seen in from anywhere in the sphere (c, r): within beta = alpha +
// asin(r / d) of the direction u to the box's centre, alpha = the largest angle between u and
// a box corner seen from c (the box lies in that cone, a convex one while alpha < pi/2), d =
// the distance from c to the box. False if that cone is a half-space or more (no use).
bool cells_seeing_box(const EarthCellTable& cells, const Eigen::Vector3d& c, double r, const Eigen::AlignedBox3d& box,
                      std::array<bool, kEarthCells>& seen) {
  const double d_box = box.exteriorDistance(c);
  const Eigen::Vector3d u = (box.center() - c).normalized();
  double cos_alpha = 1.0;
  for (int k = 0; k < 8; ++k)
    cos_alpha = std::min(cos_alpha, u.dot((box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)) - c).normalized()));
  const double beta = d_box > r && cos_alpha > 0.0 ? std::acos(std::min(1.0, cos_alpha)) + std::asin(r / d_box) : kPi;
  if (beta >= 0.5 * kPi) return false;
  const double cos_b = std::cos(beta), sin_b = std::sin(beta);
  for (int k = 0; k < kEarthCells; ++k)  // angle(cell, u) <= beta + radius, through cosines
    seen[k] = cells.dir[k].dot(u) >= cos_b * cells.cos_radius[k] - sin_b * cells.sin_radius[k] - 1e-9;
  return true;
}

// A trial's shortcut for a side whose every ray kept its reference outcome (the common case:
// on the sample, 60 % of the Earth rays a trial generated were on such sides): only the rays
// whose direction cell can reach the changed region are generated and tested; if all are clear
// the side is replayed from the reference (view factor, error, kept rays) without generating
// the others. Otherwise it is traced as usual, so results are the same bit for bit.
struct EarthReplay {
  const LoadSamples* ref = nullptr;
  bool need_rays = false;  // copy the reference's kept rays of replayed sides (lighting sums)
  std::atomic<int>* replayed_sides = nullptr;  // counts the sides replayed so
};

// `rays` = #sides rays for a side whose view is partly blocked (the pilot decides).
EarthHits earth_hits(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                     const Eigen::Vector3d& earth_dir_in, double distance_m, const Eigen::VectorXi& side_rays,
                     int pilot_rays, std::uint64_t seed, const tracing::SobolTable& sobol,
                     const std::vector<char>& may_be_blocked, const PassContext& pass,
                     const std::vector<char>* todo = nullptr, bool flatten = true, const EarthReplay& replay = {}) {
  const int ns = sides.size();
  EarthHits out;
  out.rays.resize(ns);
  out.view_factor = Eigen::VectorXd::Zero(ns);
  out.relative_error = Eigen::VectorXd::Zero(ns);
  out.replayed.assign(ns, 0);
  const Eigen::Vector3d earth_dir = earth_dir_in.normalized();
  const double R2 = kEarthRadius_m * kEarthRadius_m;
  const double sin_half = kEarthRadius_m / distance_m;
  const double cos_half = std::sqrt(1.0 - sin_half * sin_half);
  const double cap_over_pi = 2.0 * (1.0 - cos_half);  // Omega_cap / pi
  Eigen::Vector3d et, eu;
  orthonormal_frame(earth_dir, et, eu);
  const Eigen::Vector3f fe = earth_dir.cast<float>(), ft = et.cast<float>(), fu = eu.cast<float>();
  const float one_minus_cos_half = float(1.0 - cos_half);
  const bool recording = pass.recording();
  const EarthCellTable cells(earth_dir, et, eu, cos_half);
  const RayRecords* ref_records = pass.ref_records;
  const bool can_replay = replay.ref && !recording && pass.change && !pass.change->nothing && ref_records &&
                          !ref_records->empty() &&
                          static_cast<std::int64_t>(ref_records->sample_index.size()) == ref_records->ray_begin.back() &&
                          static_cast<std::int64_t>(ref_records->cell.size()) == ref_records->ray_begin.back() &&
                          replay.ref->earth_relative_error.size() == replay.ref->earth_view_factor.size();
  Eigen::AlignedBox3d change_box;  // the changed region, margin included
  if (can_replay) change_box = Eigen::AlignedBox3d(pass.change->box.min().cast<double>(), pass.change->box.max().cast<double>());
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 16), [&](const tbb::blocked_range<int>& range) {
    SideTracer tracer(scene, recording, pass.change);
    SideRays rays_out;
    std::vector<std::uint8_t> status;               // patch_side: per recorded ray, blocked now
    std::vector<std::int64_t> again;                // patch_side: the rays traced again
    std::vector<std::array<float, 3>> again_o, again_d;
    std::vector<float> cos_theta;  // per traced ray
    std::vector<Eigen::Vector3f> earth_normal;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0) continue;
      if (g.normal.dot(earth_dir) <= -sin_half) continue;  // the whole Earth is below its horizon
      if (todo && !(*todo)[s]) continue;
      const auto sd = side_seeds(seed, sides.key[s], 2);
      const int rays = side_rays[s], pilot = pilot_count(rays, pilot_rays);
      const RecordCursor cursor = pass.cursor(s);
      // Ray k of this side: origin on the side (if asked) and direction in the Earth's cone;
      // false if it points behind the side (not traced, not recorded).
      auto make_ray = [&](int k, bool origin, EarthRay& ray) {
        const auto& q = sobol[k];
        const float u_a = scrambled(q[2], sd[2]), u_phi = scrambled(q[3], sd[3]);
        const float u3 = u_a * one_minus_cos_half;  // 1 - cos(angle to the Earth's centre)
        ray.cos_a = 1.0f - u3;
        ray.sin_a = std::sqrt(std::max(0.0f, u3 * (1.0f + ray.cos_a)));
        ::sincosf(float(2.0 * kPi) * u_phi, &ray.sp, &ray.cp);
        for (int i = 0; i < 3; ++i) ray.d[i] = ray.cos_a * fe[i] + ray.sin_a * (ray.cp * ft[i] + ray.sp * fu[i]);
        ray.cos_t = g.fn[0] * ray.d[0] + g.fn[1] * ray.d[1] + g.fn[2] * ray.d[2];
        if (ray.cos_t <= 0.0f) return false;
        if (origin) on_side(g, scrambled(q[0], sd[0]), scrambled(q[1], sd[1]), ray.o);
        ray.cell = earth_cell(u_a, u_phi);
        return true;
      };
      // Earth normal at the hit of a ray, seen from the body origin (the craft's metres are
      // nothing against the Earth's radius): the ray at angle a from the centre direction meets
      // the sphere at t = D cos a - sqrt(R^2 - D^2 sin^2 a). In double: D^2 ~ 5e13 m^2.
      auto normal_at_hit = [&](const EarthRay& ray) {
        const double ca = ray.cos_a, sa = ray.sin_a;
        const double t_hit = distance_m * ca - std::sqrt(std::max(0.0, R2 - distance_m * distance_m * sa * sa));
        const double n_axis = (t_hit * ca - distance_m) / kEarthRadius_m, n_side = t_hit * sa / kEarthRadius_m;
        Eigen::Vector3f n_earth;
        for (int i = 0; i < 3; ++i) n_earth[i] = float(n_axis * fe[i] + n_side * (ray.cp * ft[i] + ray.sp * fu[i]));
        return n_earth;
      };
      // A trial's side whose reference rays are recorded: only its rays in the `seen` cells are
      // generated; each that may meet the changed faces (ChangeBox::clear_before_tracing) is
      // traced again in the candidate. No outcome changed: the side is the reference's (replayed).
      // Some did: its hits are rebuilt from the record (cosines, and the reference's Earth
      // normals of the rays it kept), generating only the rays newly unblocked: the same
      // numbers, in the same order, as tracing the side again. False (nothing written) where
      // the record cannot tell: the side is then traced as usual.
      auto patch_side = [&](int s, const RecordCursor& cursor, const std::array<bool, kEarthCells>& seen,
                            SideTracer& tracer, EarthHits& out) {
        const RayRecords& rec = *cursor.rec;
        const int r_s = (*pass.ref_side)[s];
        const auto& ref_kept = replay.ref->earth[r_s];
        const bool has_cos = static_cast<std::int64_t>(rec.cos_theta.size()) == rec.ray_begin.back();
        // The rays as traced, if recorded (else generated again, the same numbers).
        const float* recorded_od = static_cast<std::int64_t>(rec.origin_direction.size()) == 6 * rec.ray_begin.back()
                                       ? rec.origin_direction.data() + 6 * cursor.ray0
                                       : nullptr;
        status.resize(cursor.count);
        again.clear();
        again_o.clear();
        again_d.clear();
        std::int64_t hit = cursor.hit;
        long kept_ref = 0;
        for (std::int64_t i = 0; i < cursor.count; ++i) {
          const bool b = cursor.bit(i);
          status[i] = b;
          kept_ref += !b;
          const float t = b ? rec.hit_m[hit++] : kInf;
          if (!seen[rec.cell[cursor.ray0 + i]]) continue;
          EarthRay ray;
          const float *o = ray.o, *d = ray.d;
          if (recorded_od) {
            o = recorded_od + 6 * i;
            d = o + 3;
          } else if (!make_ray(static_cast<int>(rec.sample_index[cursor.ray0 + i]), true, ray)) {
            return false;  // not the reference's ray
          }
          if (pass.change->clear_before_tracing(o, d, t)) continue;
          again.push_back(i);
          std::copy(o, o + 3, again_o.emplace_back().begin());
          std::copy(d, d + 3, again_d.emplace_back().begin());
        }
        if (!again.empty()) {
          if (!has_cos || kept_ref != static_cast<long>(ref_kept.size())) return false;
          SideRays traced;
          tracer.begin(&traced);
          for (std::size_t k = 0; k < again.size(); ++k) tracer.add(again_o[k].data(), again_d[k].data());
          tracer.flush();
          for (std::size_t k = 0; k < again.size(); ++k) status[again[k]] = traced.blocked[k];
        }
        bool changed = false;
        for (std::int64_t i = 0; i < cursor.count && !changed; ++i) changed = status[i] != cursor.bit(i);
        const long reused_here = cursor.count - static_cast<long>(again.size());
        if (!changed) {
          tracer.reused += reused_here;
          out.replayed[s] = 1;
          out.view_factor[s] = replay.ref->earth_view_factor[r_s];
          out.relative_error[s] = replay.ref->earth_relative_error[r_s];
          if (replay.need_rays) out.rays[s] = ref_kept;
          if (replay.replayed_sides) replay.replayed_sides->fetch_add(1);
          return true;
        }
        // The pilot's decision (all rays or the pilot only; may_be_blocked here and in the
        // reference) must not have changed, else the record holds other rays than a trace would.
        const int rays = side_rays[s], pilot = pilot_count(rays, pilot_rays);
        int n_pilot = 0, blocked_ref = 0, blocked_now = 0;
        for (std::int64_t i = 0; i < cursor.count; ++i)
          if (static_cast<int>(rec.sample_index[cursor.ray0 + i]) < pilot) {
            ++n_pilot;
            blocked_ref += cursor.bit(i);
            blocked_now += status[i];
          }
        const bool all_now = rays > pilot && blocked_now < n_pilot;
        if (n_pilot == 0 || all_now != (rays > pilot && blocked_ref < n_pilot)) return false;
        tracer.reused += reused_here;
        // As below: the ratio estimator over the same rays and cosines.
        const float* cos_t = rec.cos_theta.data() + cursor.ray0;
        double all = 0.0;
        for (std::int64_t i = 0; i < cursor.count; ++i) all += cos_t[i];
        const double f_open = unobstructed_earth_view_factor(geo[s].normal.dot(earth_dir), distance_m);
        const double weight = all > 0.0 ? f_open / all : cap_over_pi / (all_now ? rays : pilot);
        auto& keep = out.rays[s];
        keep.clear();
        double f = 0.0;
        std::size_t j = 0;  // the reference's kept rays, in order
        for (std::int64_t i = 0; i < cursor.count; ++i) {
          const bool was_blocked = cursor.bit(i);
          if (!status[i]) {
            Eigen::Vector3f n;
            if (!was_blocked) {
              n = ref_kept[j].second;
            } else {
              EarthRay ray;
              make_ray(static_cast<int>(rec.sample_index[cursor.ray0 + i]), false, ray);
              n = normal_at_hit(ray);
            }
            keep.emplace_back(float(weight * cos_t[i]), n);
            f += weight * cos_t[i];
          }
          j += !was_blocked;
        }
        out.view_factor[s] = f;
        const double p = f_open > 0.0 ? f / f_open : 0.0;
        if (p > 0.0 && p < 1.0 - 1e-12) out.relative_error[s] = std::sqrt((1.0 - p) / (p * double(cursor.count)));
        return true;
      };
      // (Same blocking decision as the reference's, else its record may hold only the pilot.)
      // `seen`: the cells whose rays may reach the change; the others keep their reference
      // outcome, also when the side is traced again below.
      std::array<bool, kEarthCells> seen;
      bool have_seen = false;
      if (can_replay && cursor.rec && may_be_blocked[s] &&
          replay.ref->earth_may_be_blocked.size() == replay.ref->key.size() &&
          replay.ref->earth_may_be_blocked[(*pass.ref_side)[s]]) {
        Eigen::Vector3d c;
        const double r = side_bounding_sphere(g, c);
        have_seen = cells_seeing_box(cells, c, r, change_box, seen);
        if (!have_seen) seen.fill(true);  // (near the change: every ray is looked at)
        if (patch_side(s, cursor, seen, tracer, out)) continue;
      }
      const long traced_before = tracer.traced;
      tracer.begin(&rays_out, cursor);
      cos_theta.clear();
      earth_normal.clear();
      auto add_rays = [&](int from, int to) {
        for (int k = from; k < to; ++k) {
          EarthRay ray;
          if (!make_ray(k, false, ray)) continue;
          const Eigen::Vector3f n_earth = normal_at_hit(ray);
          if (may_be_blocked[s]) {
            if (!(have_seen && !seen[ray.cell] && tracer.add_reused())) {
              on_side(g, scrambled(sobol[k][0], sd[0]), scrambled(sobol[k][1], sd[1]), ray.o);
              tracer.add(ray.o, ray.d);
            }
          } else {
            tracer.add_open();  // exact: no face can meet these rays
          }
          if (recording) {
            rays_out.sample_index.push_back(static_cast<std::uint32_t>(k));
            rays_out.cell.push_back(ray.cell);
            rays_out.cos_theta.push_back(ray.cos_t);
            if (!may_be_blocked[s]) on_side(g, scrambled(sobol[k][0], sd[0]), scrambled(sobol[k][1], sd[1]), ray.o);
            rays_out.origin_direction.insert(rays_out.origin_direction.end(), ray.o, ray.o + 3);
            rays_out.origin_direction.insert(rays_out.origin_direction.end(), ray.d, ray.d + 3);
          }
          cos_theta.push_back(ray.cos_t);
          earth_normal.push_back(n_earth);
        }
        tracer.flush();
      };
      // Pilot: a side none of whose first `pilot` rays is blocked and that no face can block
      // (may_be_blocked) sees the Earth unobstructed and keeps those (its view factor is the
      // closed form, the pilot rays serve the albedo lighting); a side
      // all of whose pilot rays are blocked (e.g. an internal wall) sees none of it; only sides
      // with both trace all `rays`, where the visibility edge needs them.
      add_rays(0, pilot);
      if (cos_theta.empty()) continue;
      int used = pilot, n_blocked = 0;
      for (auto b : rays_out.blocked) n_blocked += b != 0;
      const int n_pilot = static_cast<int>(cos_theta.size());
      const bool mixed = (n_blocked > 0 && n_blocked < n_pilot) || (n_blocked == 0 && may_be_blocked[s]);
      if (mixed && rays > pilot) {
        add_rays(pilot, rays);
        used = rays;
      }
      if (recording) pass.recorder->keep(*pass.record, s, rays_out);
      out.replayed[s] = cursor.rec != nullptr && tracer.traced == traced_before;
      // Ratio estimator: the unobstructed view factor has a closed form, only the blocked
      // share is left to the rays, F = F_open x (sum over unblocked rays of cos theta) / (sum
      // over all rays of cos theta). An unobstructed side is then exact and a partly blocked
      // one only carries the (correlated, hence much smaller) error of the ratio. The albedo
      // weights are scaled alike.
      double all = 0.0;
      for (float c : cos_theta) all += c;
      const double f_open = unobstructed_earth_view_factor(g.normal.dot(earth_dir), distance_m);
      const double weight = all > 0.0 ? f_open / all : cap_over_pi / used;
      auto& keep = out.rays[s];
      keep.reserve(cos_theta.size());
      double f = 0.0;
      for (size_t k = 0; k < cos_theta.size(); ++k)
        if (!rays_out.blocked[k]) {
          keep.emplace_back(float(weight * cos_theta[k]), earth_normal[k]);
          f += weight * cos_theta[k];
        }
      out.view_factor[s] = f;
      const double p = f_open > 0.0 ? f / f_open : 0.0;
      if (p > 0.0 && p < 1.0 - 1e-12) out.relative_error[s] = std::sqrt((1.0 - p) / (p * double(cos_theta.size())));
    }
    pass.count(tracer);
  });
  if (flatten) out.flatten();
  return out;
}

// For attitudes in which the Earth moves in body axes (sun-pointing, inertial), tracing Earth
// rays at every step would cost steps x the nadir case. Instead each side traces once a set of
// cosine-weighted hemisphere rays and keeps the directions that escape the spacecraft; at each
// step, the escaping directions that point into the Earth's cone are its Earth hits
// (F = hits / N). The spacecraft is treated as a point against the Earth distance (metres
// against thousands of kilometres). Noisier than the cone sampling at equal ray counts (the
// cone edge is a discontinuity of the integrand), but independent of the step count.
struct EscapingRays {
  Eigen::Matrix<float, Eigen::Dynamic, 3> directions;  // all sides, side s owning [begin[s], begin[s+1])
  std::vector<int> begin;
  Eigen::VectorXi rays;  // per side: rays traced (escaping or not)
};

std::vector<std::vector<Eigen::Vector3f>> escaping_directions(const RayScene& scene, const std::vector<Side>& geo,
                                                             const SurfaceSides& sides, const Eigen::VectorXi& rays, std::uint64_t seed,
                                                             const tracing::SobolTable& sobol, const PassContext& pass,
                                                             const std::vector<char>* todo) {
  const int ns = sides.size();
  std::vector<std::vector<Eigen::Vector3f>> per_side(ns);
  const bool recording = pass.recording();
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 16), [&](const tbb::blocked_range<int>& range) {
    SideTracer tracer(scene, recording, pass.change);
    SideRays rays_out;
    std::vector<Eigen::Vector3f> dirs;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0 || (todo && !(*todo)[s])) continue;
      Eigen::Vector3d t, u;
      orthonormal_frame(g.normal, t, u);
      const Eigen::Vector3f ft = t.cast<float>(), fu = u.cast<float>();
      const auto sd = side_seeds(seed, sides.key[s], 3);
      tracer.begin(&rays_out, pass.cursor(s));
      dirs.clear();
      for (int k = 0; k < rays[s]; ++k) {
        const auto& q = sobol[k];
        const float r2 = scrambled(q[2], sd[2]);
        const float st = std::sqrt(r2), ct = std::sqrt(std::max(0.0f, 1.0f - r2));  // Malley
        float sp, cp;
        ::sincosf(float(2.0 * kPi) * scrambled(q[3], sd[3]), &sp, &cp);
        float o[3], d[3];
        for (int i = 0; i < 3; ++i) d[i] = st * cp * ft[i] + st * sp * fu[i] + ct * g.fn[i];
        on_side(g, scrambled(q[0], sd[0]), scrambled(q[1], sd[1]), o);
        tracer.add(o, d);
        dirs.emplace_back(d[0], d[1], d[2]);
      }
      tracer.flush();
      if (recording) pass.recorder->keep(*pass.record, s, rays_out);
      for (int k = 0; k < rays[s]; ++k)
        if (!rays_out.blocked[k]) per_side[s].push_back(dirs[k]);
    }
    pass.count(tracer);
  });
  return per_side;
}

EscapingRays pack_escaping(const std::vector<std::vector<Eigen::Vector3f>>& per_side, const Eigen::VectorXi& rays) {
  const int ns = static_cast<int>(per_side.size());
  EscapingRays out;
  out.rays = rays;
  out.begin.assign(ns + 1, 0);
  for (int s = 0; s < ns; ++s) out.begin[s + 1] = out.begin[s] + static_cast<int>(per_side[s].size());
  out.directions.resize(out.begin.back(), 3);
  for (int s = 0; s < ns; ++s)
    for (size_t k = 0; k < per_side[s].size(); ++k) out.directions.row(out.begin[s] + k) = per_side[s][k].transpose();
  return out;
}

// Per side, at one step: F_side->Earth and sum over Earth hits of w max(0, n_E . sun).
void earth_view_from_escaping(const EscapingRays& esc, const Eigen::Vector3d& earth_dir_in, double distance_m,
                              const Eigen::Vector3d& sun, Eigen::VectorXd& view_factor, Eigen::VectorXd& lit_sum) {
  const int ns = static_cast<int>(esc.begin.size()) - 1;
  const Eigen::Vector3d e = earth_dir_in.normalized();
  const double sin_half = kEarthRadius_m / distance_m, cos_half = std::sqrt(1.0 - sin_half * sin_half);
  const double R2 = kEarthRadius_m * kEarthRadius_m, r2 = distance_m * distance_m;
  view_factor.setZero(ns);
  lit_sum.setZero(ns);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      double f = 0.0, lit = 0.0;
      const double w = 1.0 / std::max(1, esc.rays[s]);
      for (int k = esc.begin[s]; k < esc.begin[s + 1]; ++k) {
        const Eigen::Vector3d d = esc.directions.row(k).transpose().cast<double>();
        const double c = d.dot(e);
        if (c <= cos_half) continue;
        // Nearest intersection with the sphere of the ray from the body origin.
        const double t = distance_m * c - std::sqrt(std::max(0.0, R2 - r2 * (1.0 - c * c)));
        const Eigen::Vector3d n = (t * d - distance_m * e) / kEarthRadius_m;
        f += w;
        lit += w * std::max(0.0, n.dot(sun));
      }
      view_factor[s] = f;
      lit_sum[s] = lit;
    }
  });
}

bool same_direction(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm() < 1e-12; }

}  // namespace

double unobstructed_earth_view_factor(double cos_angle, double distance_m) {
  // Differential plane element to a sphere (Howell's catalog, configuration B-?: "plane
  // element to sphere, element tilted"): cos(phi) / H^2 while the whole sphere is above the
  // element's horizon, the horizon-cut formula in between, 0 when it is all below.
  const double H = distance_m / kEarthRadius_m;
  if (!(H > 1.0)) throw InvalidInput("Earth view factor: distance must exceed the Earth radius");
  const double c = std::clamp(cos_angle, -1.0, 1.0);
  if (c >= 1.0 / H) return c / (H * H);
  if (c <= -1.0 / H) return 0.0;
  const double sn = std::sqrt(std::max(0.0, 1.0 - c * c));
  const double x = std::sqrt(H * H - 1.0);
  const double f = 0.5 - std::asin(std::min(1.0, x / (H * sn))) / kPi +
                   (c * std::acos(std::clamp(-x * c / sn, -1.0, 1.0)) - x * std::sqrt(std::max(0.0, 1.0 - H * H * c * c))) /
                       (kPi * H * H);
  return std::max(0.0, f);
}

Eigen::VectorXd earth_view_factors(const RayScene& scene, const SurfaceSides& sides,
                                   const Eigen::Vector3d& earth_direction_body, double distance_m, int rays,
                                   std::uint64_t seed) {
  if (rays < 1) throw InvalidInput("earth_rays_per_face must be >= 1");
  if (!(distance_m > kEarthRadius_m)) throw InvalidInput("Earth view factors: distance must exceed the Earth radius");
  const auto geo = side_geometry(scene.mesh(), sides);
  const auto table = tracing::shared_sobol_table(rays);
  const tracing::SobolTable& sobol = *table;
  const auto may_be_blocked = may_be_blocked_from_earth(geo, occluders(geo, sides), earth_direction_body.normalized(),
                                                        kEarthRadius_m / distance_m, nullptr);
  const EarthHits hits = earth_hits(scene, geo, sides, earth_direction_body, distance_m,
                                    Eigen::VectorXi::Constant(sides.size(), rays), rays, seed, sobol, may_be_blocked,
                                    PassContext{});
  return hits.view_factor;
}

Loads external_loads(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
                     const FaceViewFactors* view_factors, const ExternalLoadSettings& settings,
                     const std::function<void(const std::string&)>& progress, LoadSamples* samples,
                     LoadReuse* reuse, Eigen::MatrixXd* solar_incident_W) {
  const Environment& env = model.environment;
  if (settings.sun_rays_per_face < 1) throw InvalidInput("sun_rays_per_face must be >= 1");
  if (settings.earth_pilot_rays < 1) throw InvalidInput("earth_pilot_rays must be >= 1");
  if (settings.sun_pilot_rays < 1) throw InvalidInput("sun_pilot_rays must be >= 1");
  if (settings.earth_rays_per_face < 1) throw InvalidInput("earth_rays_per_face must be >= 1");
  const int num_nodes = static_cast<int>(model.nodes.size());
  const int ns = sides.size();
  const auto geo = side_geometry(scene.mesh(), sides);
  const Eigen::VectorXd alpha = side_absorptivity(model, sides);
  const Eigen::VectorXd eps = side_emissivity(model, sides);

  const bool orbit = env.type == EnvironmentType::orbit;
  const int steps = orbit ? (settings.steps_per_orbit > 0 ? settings.steps_per_orbit : model.analysis.steps_per_orbit) : 1;
  if (orbit && steps < 2) throw InvalidInput("analysis.steps_per_orbit must be >= 2 for an orbit");
  Loads loads;
  loads.period_s = orbit ? orbit_period_s(env.altitude_km) : 0.0;
  loads.times_s = Eigen::VectorXd::LinSpaced(steps, 0.0, loads.period_s * (steps - 1) / steps);
  if (!orbit) loads.times_s = Eigen::VectorXd::Zero(1);
  loads.in_shadow.assign(steps, 0);
  for (auto* m : {&loads.solar_W, &loads.albedo_W, &loads.earth_ir_W, &loads.reflected_solar_W,
                 &loads.sampling_standard_error_W})
    *m = Eigen::MatrixXd::Zero(num_nodes, steps);

  double flux;
  std::vector<OrbitState> states;
  if (orbit) {
    flux = solar_flux_on_day_W_per_m2(env.day_of_year);
    for (int k = 0; k < steps; ++k) states.push_back(orbit_state(env, loads.times_s[k]));
  } else {
    flux = env.solar_flux_W_per_m2;
    if (!(flux >= 0.0)) throw InvalidInput("environment.solar_flux_W_per_m2 must be >= 0");
    if (!(env.sun_direction.norm() > 0.0)) throw InvalidInput("environment.sun_direction must be non-zero");
    OrbitState st;
    st.sun_direction_body = env.sun_direction.normalized();
    states.push_back(st);
  }

  // Reuse: map sides to the reference's by identity; a side is reusable for a ray family only
  // if the family cannot reach the changed region (conservative sphere tests below).
  std::vector<int> ref_of(ns, -1);
  const LoadSamples* ref = reuse ? reuse->reference : nullptr;
  // Sample counts per side (small nodes get more): a side whose count differs from its
  // reference twin's (its node gained or lost faces) draws other samples and is not reused.
  const Eigen::VectorXi sun_rays = rays_per_side_of_node(sides, settings.sun_rays_per_face, settings.sun_min_rays_per_node, sides.load_boost);
  const Eigen::VectorXi earth_rays =
      rays_per_side_of_node(sides, settings.earth_rays_per_face, settings.earth_min_rays_per_node, sides.load_boost);
  auto same_counts = [&](int s) {
    return ref_of[s] >= 0 && ref->sun_rays.size() == static_cast<Eigen::Index>(ref->key.size()) &&
           ref->sun_rays[ref_of[s]] == sun_rays[s] && ref->earth_rays[ref_of[s]] == earth_rays[s];
  };
  // One Sobol table for every pass (the largest count any side or pilot draws).
  int max_rays = std::max({settings.sun_pilot_rays, settings.earth_pilot_rays, settings.earth_rays_per_face, 1});
  if (ns > 0) max_rays = std::max({max_rays, sun_rays.maxCoeff(), earth_rays.maxCoeff()});
  const auto table = tracing::shared_sobol_table(max_rays);
  const tracing::SobolTable& sobol = *table;
  const Occluders occ = occluders(geo, sides);
  Eigen::Vector3d change_centre = Eigen::Vector3d::Zero();
  double change_radius = 0.0;
  if (ref) {
    if (ref->sunlit.cols() != steps || static_cast<int>(ref->key.size()) != ref->sunlit.rows())
      throw InvalidInput("external loads: reference samples are for another environment or step count");
    std::unordered_map<std::uint64_t, int> index;
    for (size_t i = 0; i < ref->key.size(); ++i) index.emplace(ref->key[i], static_cast<int>(i));
    for (int s = 0; s < ns; ++s) {
      const auto it = index.find(sides.key[s]);
      if (it != index.end()) ref_of[s] = it->second;
    }
    if (!reuse->changed_region.isEmpty()) {
      change_centre = reuse->changed_region.center();
      change_radius = 0.5 * reuse->changed_region.diagonal().norm();
    } else {
      change_radius = -1.0;  // nothing changed: everything present is reusable
    }
  }
  // Per-ray reuse: a side with the same sample counts as its reference twin reads the
  // reference's record of its rays (same rays, same order); the others trace everything.
  const ChangeBox change_box = ref ? ChangeBox(reuse->changed_region, reuse->changed_faces, scene.mesh().num_faces()) : ChangeBox();
  const bool per_ray_reuse = ref && ref->per_ray;
  std::vector<int> ref_side(ns, -1);
  if (per_ray_reuse)
    for (int s = 0; s < ns; ++s) ref_side[s] = same_counts(s) ? ref_of[s] : -1;
  std::atomic<long> reused_sun_rays{0}, traced_sun_rays{0}, reused_earth_rays{0}, traced_earth_rays{0};
  // Recording (reference runs only: a run that itself reuses records nothing per ray).
  Recorder recorder;
  recorder.budget = settings.ray_record_budget_bytes;
  recorder.geometry_budget = settings.earth_ray_geometry_budget_bytes;
  const bool record = samples && !reuse;
  std::vector<SideRays> recorded;
  auto make_pass = [&](const RayRecords* ref_records, std::atomic<long>* reused_rays, std::atomic<long>* traced_rays) {
    PassContext pass;
    pass.change = &change_box;
    if (per_ray_reuse && ref_records && !ref_records->empty()) {
      pass.ref_records = ref_records;
      pass.ref_side = &ref_side;
    }
    if (record && recorder.active()) {
      recorded.assign(ns, SideRays{});
      pass.record = &recorded;
      pass.recorder = &recorder;
    }
    pass.reused_rays = reused_rays;
    pass.traced_rays = traced_rays;
    return pass;
  };
  // Bounding sphere of each side (plus its ray lift) against the changed region's sphere.
  auto side_sphere = [&](int s, Eigen::Vector3d& c) {
    const Side& g = geo[s];
    c = (g.a + g.b + g.c) / 3.0;
    return std::max({(g.a - c).norm(), (g.b - c).norm(), (g.c - c).norm()}) + 2.0 * g.offset + 1e-9;
  };
  // The side's rays all leave forwards (n . d > 0) from within its bounding sphere, so they
  // stay in the half-space n . x >= n . c - rho: a region wholly behind it is out of reach.
  auto change_behind = [&](int s) {
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    const Eigen::Vector3d& n = geo[s].normal;
    const Eigen::AlignedBox3d& box = reuse->changed_region;
    const double support = n.dot(box.center()) + n.cwiseAbs().dot(0.5 * box.diagonal());
    return support < n.dot(c) - rho - 1e-9 * (1.0 + box.diagonal().norm() + c.norm());
  };
  // With the changed faces themselves (LoadReuse::changed_faces): a sphere tree over them, so
  // that a side is tested against the changed faces, not against their bounding box (a
  // decimated CAD part spread along the craft has a box that covers most of it).
  std::vector<Eigen::Vector3d> changed_centre;
  std::vector<double> changed_radius;
  blockers::SphereTree changed_tree;
  if (ref && reuse->changed_faces) {
    const Mesh& m = reuse->changed_faces->mesh();
    std::vector<int> members(m.num_faces());
    changed_centre.resize(m.num_faces());
    changed_radius.resize(m.num_faces());
    auto corner = [&](int f, int k) -> Eigen::Vector3d { return m.V.row(m.F(f, k)).transpose(); };
    for (int f = 0; f < m.num_faces(); ++f) {
      members[f] = f;
      changed_centre[f] = (corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3.0;
      double r = 0.0;
      for (int k = 0; k < 3; ++k) r = std::max(r, (corner(f, k) - changed_centre[f]).norm());
      // float rounding of the traced coordinates, as the box's margin
      changed_radius[f] = r + 1e-6 * (changed_centre[f].cwiseAbs().maxCoeff() + r) + 1e-9;
    }
    std::vector<std::array<Eigen::Vector3d, 3>> corners(m.num_faces());
    for (int f = 0; f < m.num_faces(); ++f) corners[f] = {corner(f, 0), corner(f, 1), corner(f, 2)};
    changed_tree = blockers::sphere_tree(members, changed_centre, changed_radius,
                                         [&](int f, int k) -> const Eigen::Vector3d& { return corners[f][k]; });
  }
  // Some changed face's sphere meets the side's sphere swept along d (`swept`) or the cone
  // it sees the Earth through (`cone`); conservative, as the box tests.
  auto changed_face_meets = [&](int s, auto&& meets) {
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    return blockers::any_member(
        changed_tree, [&](const blockers::SphereTree::Node& n) { return meets(n.centre - c, rho + n.radius); },
        [&](int f) { return meets(changed_centre[f] - c, rho + changed_radius[f]); });
  };
  auto clear_of_change_along = [&](int s, const Eigen::Vector3d& d) {  // half-line family c + t d
    if (change_radius < 0.0 || change_behind(s)) return true;
    if (!changed_tree.nodes.empty() &&
        !changed_face_meets(s, [&](const Eigen::Vector3d& v, double reach) {
          const double along = v.dot(d);
          return along >= -reach && v.squaredNorm() - along * along <= reach * reach * (1.0 + 1e-9);
        }))
      return true;
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    const Eigen::Vector3d bc = change_centre - c;
    const double t = std::max(0.0, bc.dot(d));
    if ((bc - t * d).norm() > rho + change_radius) return true;
    // Tighter for flat or long regions: the swept sphere {c + t d + r, |r| <= rho} meets the
    // region only if the half-line from c meets the region grown by rho (slab test).
    const Eigen::AlignedBox3d& box = reuse->changed_region;
    const double grow = rho + 1e-9 * (1.0 + box.diagonal().norm());
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const double lo = box.min()[k] - grow, hi = box.max()[k] + grow;
      if (d[k] == 0.0) {
        if (c[k] < lo || c[k] > hi) return true;
        continue;
      }
      double ta = (lo - c[k]) / d[k], tb = (hi - c[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return true;
    }
    // Exact for the side itself: its rays leave the triangle (lifted by up to its offset)
    // along d, i.e. they fill a prism; it misses the region if some axis separates them
    // (separating axes of a prism along d and a box: the prism's side normals e x d, the
    // box's axes x d, and d itself for a region behind). On the sample, 8 of every 14 sides
    // the sphere tests kept had no ray entering the region.
    const Side& g = geo[s];
    const Eigen::Vector3d lift = g.normal * g.offset;
    const std::array<Eigen::Vector3d, 6> corner = {g.a, g.b, g.c, g.a + lift, g.b + lift, g.c + lift};
    const Eigen::Vector3d half = 0.5 * box.sizes() + Eigen::Vector3d::Constant(1e-5 * (1.0 + box.diagonal().norm() + c.norm() + rho));
    auto separates = [&](const Eigen::Vector3d& axis, bool half_line) {
      const double len = axis.norm();
      if (!(len > 1e-9)) return false;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& v : corner) {
        lo = std::min(lo, v.dot(axis));
        hi = std::max(hi, v.dot(axis));
      }
      const double centre = box.center().dot(axis), reach = half.dot(axis.cwiseAbs());
      if (half_line) return centre + reach < lo;  // all of the region behind the prism's start
      return centre + reach < lo || centre - reach > hi;
    };
    if (separates(d, true)) return true;
    const std::array<Eigen::Vector3d, 3> edge = {g.b - g.a, g.c - g.b, g.a - g.c};
    for (const auto& e : edge)
      if (separates(e.cross(d), false)) return true;
    for (int k = 0; k < 3; ++k)
      if (separates(Eigen::Vector3d::Unit(k).cross(d), false)) return true;
    return false;
  };
  auto clear_of_change_in_cone = [&](int s, const Eigen::Vector3d& axis, double half_angle) {
    if (change_radius < 0.0 || change_behind(s)) return true;
    if (!changed_tree.nodes.empty() &&
        !changed_face_meets(s, [&](const Eigen::Vector3d& v, double reach) {
          const double dist = v.norm();
          if (dist <= reach) return true;
          const double angle = std::acos(std::clamp(v.dot(axis) / dist, -1.0, 1.0));
          return angle <= half_angle + std::asin(std::min(1.0, reach / dist)) + 1e-9;
        }))
      return true;
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    const Eigen::Vector3d bc = change_centre - c;
    const double dist = bc.norm(), reach = rho + change_radius;
    if (dist <= reach) return false;
    const double angle = std::acos(std::clamp(bc.dot(axis) / dist, -1.0, 1.0));
    return angle > half_angle + std::asin(std::min(1.0, reach / dist)) + 1e-9;
  };
  auto clear_of_change_in_front = [&](int s) {
    if (change_radius < 0.0 || change_behind(s)) return true;
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    return (change_centre - c).dot(geo[s].normal) < -(rho + change_radius);
  };

  if (samples) {
    samples->key = sides.key;
    samples->sunlit = Eigen::MatrixXd::Zero(ns, steps);
    samples->sun_rays = sun_rays;
    samples->earth_rays = earth_rays;
    samples->earth.assign(ns, {});
    samples->earth_view_factor = Eigen::VectorXd::Zero(ns);
    samples->earth_relative_error = Eigen::VectorXd::Zero(ns);
    samples->sun_records.assign(steps, RayRecords{});
    samples->earth_records = RayRecords{};
    samples->per_ray = false;
    samples->earth_may_be_blocked.clear();
  }

  // Solar-band incident power per side and step [W] (direct and albedo), absorbed shares.
  Eigen::MatrixXd incident_direct = Eigen::MatrixXd::Zero(ns, steps);
  Eigen::MatrixXd incident_albedo = Eigen::MatrixXd::Zero(ns, steps);

  // Direct sun: one shadow computation per distinct sun direction in body axes (a single one
  // for sun-pointing and inertial attitudes or a fixed sun).
  if (progress) progress("direct sun: " + std::to_string(steps) + " step(s)");
  Eigen::Vector3d last_dir = Eigen::Vector3d::Zero();
  Eigen::VectorXd lit;
  std::vector<std::vector<std::array<float, 3>>> sun_points(ns);  // per side, for every step
  std::vector<char> todo(ns, 1);
  for (int k = 0; k < steps; ++k) {
    const OrbitState& st = states[k];
    loads.in_shadow[k] = st.in_shadow;
    if (st.in_shadow || flux == 0.0) continue;
    if (lit.size() == 0 || !same_direction(st.sun_direction_body, last_dir)) {
      int reused_here = 0;
      if (ref)
        for (int s = 0; s < ns; ++s) {
          todo[s] = !(same_counts(s) && clear_of_change_along(s, st.sun_direction_body));
          reused_here += !todo[s];
        }
      if (reuse) {
        reuse->reused_sun += reused_here;
        reuse->total_sun += ns;
      }
      const PassContext pass = make_pass(ref && static_cast<int>(ref->sun_records.size()) == steps ? &ref->sun_records[k] : nullptr,
                                         &reused_sun_rays, &traced_sun_rays);
      lit = sunlit_fraction(scene, geo, sides, st.sun_direction_body, sun_rays, settings.sun_pilot_rays, settings.seed,
                            sobol, occ, pass, sun_points, ref ? &todo : nullptr);
      if (pass.recording() && recorder.active()) samples->sun_records[k] = pack_records(recorded);
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!todo[s]) lit[s] = ref->sunlit(ref_of[s], k);
      last_dir = st.sun_direction_body;
    }
    if (samples) samples->sunlit.col(k) = lit;
    for (int s = 0; s < ns; ++s) {
      const double full = flux * geo[s].area * std::max(0.0, geo[s].normal.dot(st.sun_direction_body));
      incident_direct(s, k) = full * lit[s];
      // Shadow-sample error of a partly lit side (lit share p of N scrambled-net points): a
      // shadow edge is a smooth curve on the face, which cuts ~sqrt(N) of the net's N strata,
      // each an error of at most 1/N: sigma_p ~ sqrt(p (1 - p)) N^-3/4 (Owen's N^-3/4 for
      // such indicators), not the binomial sqrt(p (1 - p) / N), which overstated the measured
      // seed-to-seed differences ~16x (docs/thermal.md, sessions 3 and 10). Variances are summed
      // per node here and rooted below, with the Earth rays' terms.
      const int node = sides.node[s];
      if (lit[s] > 0.0 && lit[s] < 1.0 && node >= 0 && node < num_nodes && sun_rays[s] > 0)
        loads.sampling_standard_error_W(node, k) +=
            std::pow(alpha[s] * full * std::sqrt(lit[s] * (1.0 - lit[s])) * std::pow(double(sun_rays[s]), -0.75), 2);
    }
  }

  // Earth: cone rays once if the Earth is fixed in body axes (nadir), else escaping
  // hemisphere rays once, intersected with the Earth's cone at every step.
  if (orbit) {
    if (progress) progress("Earth view factors");
    const double distance = orbit_radius_m(env.altitude_km);
    bool earth_fixed = true;
    for (int k = 1; k < steps; ++k) earth_fixed &= same_direction(states[k].earth_direction_body, states[0].earth_direction_body);
    if (ref && ref->earth_fixed != earth_fixed)
      throw InvalidInput("external loads: reference samples are for another attitude");
    const double half_angle = std::asin(kEarthRadius_m / distance);
    std::vector<char> earth_todo(ns, 1), may_be_blocked;
    if (earth_fixed) {
      // For every side (not only those traced): a side reused whole must also have taken the
      // same pilot decision, which depends on this conservative test as well as on its rays.
      may_be_blocked = may_be_blocked_from_earth(geo, occ, states[0].earth_direction_body.normalized(),
                                                 kEarthRadius_m / distance, nullptr);
      if (samples) samples->earth_may_be_blocked = may_be_blocked;
    }
    const bool ref_has_decisions = ref && static_cast<int>(ref->earth_may_be_blocked.size()) == static_cast<int>(ref->key.size());
    if (ref)
      for (int s = 0; s < ns; ++s) {
        // note: a side that no face can block, here and in the reference, has all its rays open
        // in both (never traced, the same pilot decision): reused whole wherever the change is.
        earth_todo[s] = !(same_counts(s) &&
                          (earth_fixed ? ref_has_decisions && may_be_blocked[s] == ref->earth_may_be_blocked[ref_of[s]] &&
                                             (!may_be_blocked[s] ||
                                              clear_of_change_in_cone(s, states[0].earth_direction_body.normalized(), half_angle))
                                       : clear_of_change_in_front(s)));
        reuse->reused_earth += !earth_todo[s];
        reuse->total_earth += 1;
      }
    EarthHits hits;
    EscapingRays escaping;
    // Sides traced again whose rays all kept their reference outcome: the same Earth hits as
    // the reference's, so their per-step lighting sums are copied (on the sample, half of the
    // sums a trial computed).
    std::vector<char> replayed(ns, 0);
    const bool ref_lit = ref && ref->earth_lit_per_step.rows() == steps &&
                         ref->earth_lit_per_step.cols() == static_cast<Eigen::Index>(ref->key.size());
    const PassContext pass = make_pass(ref ? &ref->earth_records : nullptr, &reused_earth_rays, &traced_earth_rays);
    std::atomic<int> replayed_by_cells{0};
    if (earth_fixed) {
      hits = earth_hits(scene, geo, sides, states[0].earth_direction_body, distance, earth_rays, settings.earth_pilot_rays,
                        settings.seed, sobol, may_be_blocked, pass, ref ? &earth_todo : nullptr, /*flatten=*/false,
                        EarthReplay{ref, samples != nullptr || !ref_lit, &replayed_by_cells});
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!earth_todo[s]) {
            // Its rays are needed only to record them; its lighting sums come from the reference.
            if (samples || !ref_lit) hits.rays[s] = ref->earth[ref_of[s]];
            hits.view_factor[s] = ref->earth_view_factor[ref_of[s]];
            if (ref->earth_relative_error.size() == ref->earth_view_factor.size())
              hits.relative_error[s] = ref->earth_relative_error[ref_of[s]];
          }
      if (ref && ref_has_decisions)
        for (int s = 0; s < ns; ++s)
          replayed[s] = earth_todo[s] && hits.replayed[s] && ref_of[s] >= 0 &&
                        may_be_blocked[s] == ref->earth_may_be_blocked[ref_of[s]];
      if (samples) {
        samples->earth = hits.rays;
        samples->earth_view_factor = hits.view_factor;
        samples->earth_relative_error = hits.relative_error;
      }
      hits.flatten();
    } else {
      // The same per-side counts as the cone sampling of the nadir case (per-node budgets,
      // noise-targeted boosts): a sun-pointing or inertial craft's Earth loads are as noisy
      // as a nadir one's at equal counts, or more (the cone's edge cuts these rays).
      auto dirs = escaping_directions(scene, geo, sides, earth_rays, settings.seed, sobol, pass,
                                      ref ? &earth_todo : nullptr);
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!earth_todo[s]) {
            dirs[s].clear();
            for (const auto& [w, d] : ref->earth[ref_of[s]]) dirs[s].push_back(d);
          }
      if (samples)
        for (int s = 0; s < ns; ++s)
          for (const auto& d : dirs[s]) samples->earth[s].emplace_back(1.0f / std::max(1, earth_rays[s]), d);
      escaping = pack_escaping(dirs, earth_rays);
    }
    if (reuse) reuse->earth_sides_replayed_by_cells = replayed_by_cells.load();
    if (pass.recording() && recorder.active()) samples->earth_records = pack_records(recorded);
    Eigen::VectorXd view_factor, lit_sum(ns);
    // Earth fixed in body axes: per side, sum over its Earth hits of w max(0, n_E . sun) at
    // every step at once (each hit read once, the steps in the inner, vectorisable loop).
    Eigen::MatrixXf lit_per_step;  // steps x #sides
    if (earth_fixed) {
      std::vector<float> sx(steps), sy(steps), sz(steps);
      for (int k = 0; k < steps; ++k) {
        sx[k] = float(states[k].sun_direction_body.x());
        sy[k] = float(states[k].sun_direction_body.y());
        sz[k] = float(states[k].sun_direction_body.z());
      }
      lit_per_step = Eigen::MatrixXf::Zero(steps, ns);
      const float* nx = hits.normals.col(0).data();
      const float* ny = hits.normals.col(1).data();
      const float* nz = hits.normals.col(2).data();
      const float* w = hits.weights.data();
      tbb::parallel_for(tbb::blocked_range<int>(0, ns, 16), [&](const tbb::blocked_range<int>& range) {
        for (int s = range.begin(); s < range.end(); ++s) {
          float* acc = lit_per_step.col(s).data();
          if (ref_lit && (!earth_todo[s] || replayed[s])) {  // the same rays, the same sums
            lit_per_step.col(s) = ref->earth_lit_per_step.col(ref_of[s]);
            continue;
          }
          for (int r = hits.begin[s]; r < hits.begin[s + 1]; ++r) {
            const float wr = w[r], ax = nx[r], ay = ny[r], az = nz[r];
            for (int k = 0; k < steps; ++k) acc[k] += wr * std::max(0.0f, ax * sx[k] + ay * sy[k] + az * sz[k]);
          }
        }
      });
    }
    if (samples && earth_fixed) samples->earth_lit_per_step = lit_per_step;
    for (int k = 0; k < steps; ++k) {
      const OrbitState& st = states[k];
      if (earth_fixed) {
        for (int s = 0; s < ns; ++s) lit_sum[s] = lit_per_step(k, s);
        view_factor = hits.view_factor;
      } else {
        earth_view_from_escaping(escaping, st.earth_direction_body, distance, st.sun_direction_body, view_factor, lit_sum);
      }
      for (int s = 0; s < ns; ++s) {
        if (view_factor[s] == 0.0) continue;
        incident_albedo(s, k) = env.albedo * flux * geo[s].area * lit_sum[s];
        const int node = sides.node[s];
        if (node < 0 || node >= num_nodes) continue;
        const double ir = eps[s] * env.earth_ir_flux_W_per_m2 * geo[s].area * view_factor[s];
        loads.earth_ir_W(node, k) += ir;
        if (earth_fixed && hits.relative_error.size() == ns)  // both scale with the unblocked share
          loads.sampling_standard_error_W(node, k) +=
              std::pow(hits.relative_error[s] * (ir + alpha[s] * incident_albedo(s, k)), 2);
        // note: the escaping rays' binomial error sqrt((1 - F) / (F N)) is left out of the
        // estimate, like the sun's shadow samples: on the sample in sun-pointing attitude it
        // asked for x8 Earth samples on the wings (4x the reduction's run time) to take the
        // measured noise floor from 0.020 K to 0.012 K (docs/thermal.md, session 5).
      }
    }
  }

  if (reuse) {
    reuse->reused_sun_rays += reused_sun_rays;
    reuse->traced_sun_rays += traced_sun_rays;
    reuse->reused_earth_rays += reused_earth_rays;
    reuse->traced_earth_rays += traced_earth_rays;
  }
  if (record) {
    samples->per_ray = recorder.active();
    if (!samples->per_ray) {  // over budget: keep none (trials use the per-side tests)
      samples->sun_records.assign(steps, RayRecords{});
      samples->earth_records = RayRecords{};
    }
  }
  if (samples) samples->earth_fixed = !orbit || [&] {
    for (int k = 1; k < steps; ++k)
      if (!same_direction(states[k].earth_direction_body, states[0].earth_direction_body)) return false;
    return true;
  }();

  loads.sampling_standard_error_W = loads.sampling_standard_error_W.cwiseSqrt();  // variances summed above
  for (int s = 0; s < ns; ++s) {
    const int node = sides.node[s];
    if (node < 0 || node >= num_nodes) continue;
    loads.solar_W.row(node) += alpha[s] * incident_direct.row(s);
    loads.albedo_W.row(node) += alpha[s] * incident_albedo.row(s);
  }

  const Eigen::MatrixXd incident = incident_direct + incident_albedo;
  if (settings.solar_reflections && view_factors) {
    if (progress) progress("solar reflections");
    add_solar_reflections(loads, model, sides, *view_factors, incident, ref, samples);
  }
  if (solar_incident_W) *solar_incident_W = incident;
  return loads;
}

void add_solar_reflections(Loads& loads, const ThermalModel& model, const SurfaceSides& sides,
                           const FaceViewFactors& view_factors, const Eigen::MatrixXd& solar_incident_W,
                           const LoadSamples* warm, LoadSamples* samples) {
  const int ns = sides.size(), num_nodes = static_cast<int>(model.nodes.size());
  if (view_factors.sides.size() != ns)
    throw InvalidInput("solar reflections: view factors are for " + std::to_string(view_factors.sides.size()) +
                       " sides, the model has " + std::to_string(ns));
  if (solar_incident_W.rows() != ns || loads.reflected_solar_W.rows() != num_nodes ||
      loads.reflected_solar_W.cols() != solar_incident_W.cols())
    throw InvalidInput("solar reflections: incident power is " + std::to_string(solar_incident_W.rows()) + " x " +
                       std::to_string(solar_incident_W.cols()) + " for " + std::to_string(ns) + " sides and loads of " +
                       std::to_string(loads.reflected_solar_W.cols()) + " steps");
  const Eigen::VectorXd alpha = side_absorptivity(model, sides);
  // A trial starts from the reference's solution (sides present in both; the others from 0).
  RowMatrixXd guess;
  const bool warm_ok = warm && warm->solar_gebhart.rows() == static_cast<Eigen::Index>(warm->key.size()) &&
                       warm->solar_gebhart.cols() == num_nodes + 2;
  if (warm_ok) {
    std::unordered_map<std::uint64_t, int> index;
    for (size_t i = 0; i < warm->key.size(); ++i) index.emplace(warm->key[i], static_cast<int>(i));
    guess = RowMatrixXd::Zero(ns, num_nodes + 2);
    for (int s = 0; s < ns; ++s) {
      const auto it = index.find(sides.key[s]);
      if (it != index.end()) guess.row(s) = warm->solar_gebhart.row(it->second);
    }
  }
  const GebhartFactors solar =
      gebhart_factors(view_factors, alpha, node_groups(sides, num_nodes), num_nodes + 1, {}, warm_ok ? &guess : nullptr);
  if (samples) samples->solar_gebhart = solar.B;
  for (int s = 0; s < ns; ++s) {
    if (solar_incident_W.row(s).isZero()) continue;
    for (int g = 0; g < num_nodes; ++g)
      if (solar.B(s, g) != 0.0) loads.reflected_solar_W.row(g) += (1.0 - alpha[s]) * solar.B(s, g) * solar_incident_W.row(s);
  }
}

}  // namespace thermodec
