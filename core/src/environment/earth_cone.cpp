// Earth view factors with the blocked share, by rays drawn inside the cone the Earth subtends.
//
// Computes, per face side, F_side->Earth = (1/pi) int cos(theta) V dw over the Earth's cone
// (V = 0 where the spacecraft blocks the view) as a ratio estimator: the closed form of the
// unobstructed element-to-sphere view factor times the unblocked share of the rays' cos theta,
// so an unobstructed side is exact and a partly blocked one carries only the binomial error of
// that share (EarthHits::relative_error, sqrt((1 - p) / (p N))). The Earth is a sphere of
// kEarthRadius_m seen from the body origin (the craft's metres are nothing against it).
// Rays: per side the ray stage's Owen-scrambled Sobol points (load_sides.h); a pilot decides
// which sides need them all. A trial replays or patches a side from the reference's per-ray
// records where its change cannot alter the outcome (ray_records.h), bit for bit.
#include "earth_cone.h"
#include "earth_raster.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec::load_rays {

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
        return may_meet_earth_cone(occ.centre[s], geo[s].normal, earth_dir, sin_half, cos_half, centre, reach);
      });
    }
  });
  return out;
}

namespace {

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

// The Earth's cone as the rays of one pass see it: axis fe and azimuth frame (ft, fu) in float
// (the rays are), 1 - cos of its half-angle, and the Earth's distance [m] and radius^2 [m^2].
struct EarthCone {
  Eigen::Vector3f fe, ft, fu;
  float one_minus_cos_half;
  double distance_m, R2, radius_m;
  // Ray k of this side: origin on the side (if asked) and direction in the Earth's cone;
  // false if it points behind the side (not traced, not recorded).
  bool make_ray(const Side& g, const std::array<std::uint32_t, 4>& sd, const tracing::SobolTable& sobol, int k,
                bool origin, EarthRay& ray) const {
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
  }
  // Earth normal at the hit of a ray, seen from the body origin (the craft's metres are
  // nothing against the Earth's radius): the ray at angle a from the centre direction meets
  // the sphere at t = D cos a - sqrt(R^2 - D^2 sin^2 a). In double: D^2 ~ 5e13 m^2.
  Eigen::Vector3f normal_at_hit(const EarthRay& ray) const {
    const double ca = ray.cos_a, sa = ray.sin_a;
    const double t_hit = distance_m * ca - std::sqrt(std::max(0.0, R2 - distance_m * distance_m * sa * sa));
    const double n_axis = (t_hit * ca - distance_m) / radius_m, n_side = t_hit * sa / radius_m;
    Eigen::Vector3f n_earth;
    for (int i = 0; i < 3; ++i) n_earth[i] = float(n_axis * fe[i] + n_side * (ray.cp * ft[i] + ray.sp * fu[i]));
    return n_earth;
  }
};

// What earth_hits' work on one side reads (the same for every side of the pass).
struct EarthPass {
  const std::vector<Side>& geo;
  const SurfaceSides& sides;
  Eigen::Vector3d earth_dir;  // unit
  double distance_m, radius_m, sin_half, cap_over_pi;
  const Eigen::VectorXi& side_rays;
  int pilot_rays;
  std::uint64_t seed;
  const tracing::SobolTable& sobol;
  const std::vector<char>& may_be_blocked;
  const PassContext& pass;
  const std::vector<char>* todo;
  const EarthReplay& replay;
  EarthCone cone;
  const EarthCellTable& cells;
  bool recording, can_replay;
  Eigen::AlignedBox3d change_box;  // the changed region, margin included (can_replay)
  const Occluders* occ;            // with `grid`: the Earth view by rasterised blockers
  const EarthGrid* grid;           // (earth_raster.h) instead of rays
};

// Per-thread scratch of earth_hits.
struct EarthScratch {
  SideRays rays_out;
  std::vector<std::uint8_t> status;               // patch_side: per recorded ray, blocked now
  std::vector<std::int64_t> again;                // patch_side: the rays traced again
  std::vector<std::array<float, 3>> again_o, again_d;
  std::vector<float> cos_theta;  // per traced ray
  std::vector<Eigen::Vector3f> earth_normal;
  RasterScratch raster;
};

// A trial's side whose reference rays are recorded: only its rays in the `seen` cells are
// generated; each that may meet the changed faces (ChangeBox::clear_before_tracing) is
// traced again in the candidate. No outcome changed: the side is the reference's (replayed).
// Some did: its hits are rebuilt from the record (cosines, and the reference's Earth
// normals of the rays it kept), generating only the rays newly unblocked: the same
// numbers, in the same order, as tracing the side again. False (nothing written) where
// the record cannot tell: the side is then traced as usual.
bool patch_side(const EarthPass& ep, int s, const std::array<std::uint32_t, 4>& sd, const RecordCursor& cursor,
                const std::array<bool, kEarthCells>& seen, SideTracer& tracer, EarthScratch& x, EarthHits& out) {
  const PassContext& pass = ep.pass;
  const EarthReplay& replay = ep.replay;
  const Eigen::VectorXi& side_rays = ep.side_rays;
  const int pilot_rays = ep.pilot_rays;
  const std::vector<Side>& geo = ep.geo;
  const Eigen::Vector3d& earth_dir = ep.earth_dir;
  const double distance_m = ep.distance_m, radius_m = ep.radius_m, cap_over_pi = ep.cap_over_pi;
  auto& status = x.status;
  auto& again = x.again;
  auto& again_o = x.again_o;
  auto& again_d = x.again_d;
  auto make_ray = [&](int k, bool origin, EarthRay& ray) { return ep.cone.make_ray(geo[s], sd, ep.sobol, k, origin, ray); };
  auto normal_at_hit = [&](const EarthRay& ray) { return ep.cone.normal_at_hit(ray); };
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
  const double f_open = unobstructed_earth_view_factor(geo[s].normal.dot(earth_dir), distance_m, radius_m);
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
}

// The Earth rays of side s: replayed or patched from the reference's record if it can tell,
// else traced (pilot first).
void trace_side(const EarthPass& ep, int s, SideTracer& tracer, EarthScratch& x, EarthHits& out) {
  const std::vector<Side>& geo = ep.geo;
  const SurfaceSides& sides = ep.sides;
  const Eigen::Vector3d& earth_dir = ep.earth_dir;
  const double sin_half = ep.sin_half, distance_m = ep.distance_m, radius_m = ep.radius_m, cap_over_pi = ep.cap_over_pi;
  const std::vector<char>* todo = ep.todo;
  const Eigen::VectorXi& side_rays = ep.side_rays;
  const int pilot_rays = ep.pilot_rays;
  const std::uint64_t seed = ep.seed;
  const PassContext& pass = ep.pass;
  const EarthReplay& replay = ep.replay;
  const std::vector<char>& may_be_blocked = ep.may_be_blocked;
  const tracing::SobolTable& sobol = ep.sobol;
  const bool recording = ep.recording, can_replay = ep.can_replay;
  const EarthCellTable& cells = ep.cells;
  const Eigen::AlignedBox3d& change_box = ep.change_box;
  SideRays& rays_out = x.rays_out;
  std::vector<float>& cos_theta = x.cos_theta;
  std::vector<Eigen::Vector3f>& earth_normal = x.earth_normal;
  const Side& g = geo[s];
  if (g.area <= 0.0) return;
  if (g.normal.dot(earth_dir) <= -sin_half) return;  // the whole Earth is below its horizon
  if (todo && !(*todo)[s]) return;
  const auto sd = side_seeds(seed, sides.key[s], 2);
  const int rays = side_rays[s], pilot = pilot_count(rays, pilot_rays);
  if (ep.grid) {
    const double f_open = unobstructed_earth_view_factor(g.normal.dot(earth_dir), distance_m, radius_m);
    const RasterView v = earth_view_by_raster(*ep.grid, geo, *ep.occ, s, may_be_blocked[s], sin_half, f_open,
                                              raster_origins(rays), rays, sd, sobol, x.raster, out.rays[s]);
    if (!v.by_rays) {
      out.view_factor[s] = v.view_factor;
      out.relative_error[s] = v.relative_error;
      return;
    }  // else traced below, with per-ray records as without the raster
  }
  const RecordCursor cursor = pass.cursor(s);
  auto make_ray = [&](int k, bool origin, EarthRay& ray) { return ep.cone.make_ray(g, sd, sobol, k, origin, ray); };
  auto normal_at_hit = [&](const EarthRay& ray) { return ep.cone.normal_at_hit(ray); };
  // (Same blocking decision as the reference's, else its record may hold only the pilot.)
  // `seen`: the cells whose rays may reach the change; the others keep their reference
  // outcome, also when the side is traced again below.
  std::array<bool, kEarthCells> seen;
  bool have_seen = false;
  if (can_replay && cursor.rec && cursor.count > 0 && may_be_blocked[s] &&
      replay.ref->earth_may_be_blocked.size() == replay.ref->key.size() &&
      replay.ref->earth_may_be_blocked[(*pass.ref_side)[s]]) {
    Eigen::Vector3d c;
    const double r = side_bounding_sphere(g, c);
    have_seen = cells_seeing_box(cells, c, r, change_box, seen);
    if (!have_seen) seen.fill(true);  // (near the change: every ray is looked at)
    if (patch_side(ep, s, sd, cursor, seen, tracer, x, out)) return;
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
  if (cos_theta.empty()) return;
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
  const double f_open = unobstructed_earth_view_factor(g.normal.dot(earth_dir), distance_m, radius_m);
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

}  // namespace

EarthHits earth_hits(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                     const Eigen::Vector3d& earth_dir_in, double distance_m, double radius_m, const Eigen::VectorXi& side_rays,
                     int pilot_rays, std::uint64_t seed, const tracing::SobolTable& sobol,
                     const std::vector<char>& may_be_blocked, const PassContext& pass,
                     const std::vector<char>* todo, bool flatten, const EarthReplay& replay, const Occluders* occ) {
  const int ns = sides.size();
  EarthHits out;
  out.rays.resize(ns);
  out.view_factor = Eigen::VectorXd::Zero(ns);
  out.relative_error = Eigen::VectorXd::Zero(ns);
  out.replayed.assign(ns, 0);
  const Eigen::Vector3d earth_dir = earth_dir_in.normalized();
  const double R2 = radius_m * radius_m;
  const double sin_half = radius_m / distance_m;
  const double cos_half = std::sqrt(1.0 - sin_half * sin_half);
  const double cap_over_pi = 2.0 * (1.0 - cos_half);  // Omega_cap / pi
  Eigen::Vector3d et, eu;
  orthonormal_frame(earth_dir, et, eu);
  const Eigen::Vector3f fe = earth_dir.cast<float>(), ft = et.cast<float>(), fu = eu.cast<float>();
  const float one_minus_cos_half = float(1.0 - cos_half);
  const bool raster = occ != nullptr;
  // (Rasterised sides record nothing: a trial computes them again whole; sides on rays record
  // and replay their rays as without the raster, a side rasterised in the reference has none.)
  const bool recording = pass.recording();
  const EarthCellTable cells(earth_dir, et, eu, cos_half);
  std::unique_ptr<EarthGrid> grid;
  if (raster) grid = std::make_unique<EarthGrid>(earth_dir, et, eu, distance_m, radius_m);
  const RayRecords* ref_records = pass.ref_records;
  const bool can_replay = replay.ref && !recording && pass.change && !pass.change->nothing && ref_records &&
                          !ref_records->empty() &&
                          static_cast<std::int64_t>(ref_records->sample_index.size()) == ref_records->ray_begin.back() &&
                          static_cast<std::int64_t>(ref_records->cell.size()) == ref_records->ray_begin.back() &&
                          replay.ref->earth_relative_error.size() == replay.ref->earth_view_factor.size();
  Eigen::AlignedBox3d change_box;  // the changed region, margin included
  if (can_replay) change_box = Eigen::AlignedBox3d(pass.change->box.min().cast<double>(), pass.change->box.max().cast<double>());
  const EarthPass ep{geo, sides, earth_dir, distance_m, radius_m, sin_half, cap_over_pi, side_rays, pilot_rays, seed, sobol,
                     may_be_blocked, pass, todo, replay, EarthCone{fe, ft, fu, one_minus_cos_half, distance_m, R2, radius_m},
                     cells, recording, can_replay, change_box, occ, grid.get()};
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 16), [&](const tbb::blocked_range<int>& range) {
    SideTracer tracer(scene, recording, pass.change);
    EarthScratch x;
    for (int s = range.begin(); s < range.end(); ++s) trace_side(ep, s, tracer, x, out);
    pass.count(tracer);
  });
  if (flatten) out.flatten();
  return out;
}

}  // namespace thermodec::load_rays

namespace thermodec {

using namespace load_rays;

double unobstructed_earth_view_factor(double cos_angle, double distance_m, double radius_m) {
  // Differential plane element to a sphere (Howell's catalog, configuration B-?: "plane
  // element to sphere, element tilted"): cos(phi) / H^2 while the whole sphere is above the
  // element's horizon, the horizon-cut formula in between, 0 when it is all below.
  const double H = distance_m / radius_m;
  if (!(H > 1.0)) throw InvalidInput("Earth view factor: distance must exceed the central body's radius");
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
                                   std::uint64_t seed, double radius_m, bool by_rays) {
  if (rays < 1) throw InvalidInput("earth_rays_per_face must be >= 1");
  if (!(distance_m > radius_m)) throw InvalidInput("Earth view factors: distance must exceed the central body's radius");
  const auto geo = side_geometry(scene.mesh(), sides);
  const auto table = tracing::shared_sobol_table(rays);
  const tracing::SobolTable& sobol = *table;
  const Occluders occ = occluders(geo, sides);
  const auto may_be_blocked = may_be_blocked_from_earth(geo, occ, earth_direction_body.normalized(),
                                                        radius_m / distance_m, nullptr);
  const EarthHits hits = earth_hits(scene, geo, sides, earth_direction_body, distance_m, radius_m,
                                    Eigen::VectorXi::Constant(sides.size(), rays), rays, seed, sobol, may_be_blocked,
                                    PassContext{}, nullptr, true, {}, by_rays ? nullptr : &occ);
  return hits.view_factor;
}

}  // namespace thermodec
