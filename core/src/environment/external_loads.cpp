// External loads: direct sun with self-shadowing, Earth albedo and IR through ray-traced
// face-to-Earth view factors, and solar-band diffuse reflections (Gebhart with absorptivity).
// The paper (Sec. III) lists the three effects that make a face's incident solar power:
// its angle to the source, occlusion by other faces, and reflections from other faces.
#include "thermodec/environment/external_loads.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <unordered_map>
#include <cmath>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"
// The radiative engine's Owen-scrambled Sobol sampler (private to the core library): the same
// sequences and side seeding as the view factors, so loads get the same variance properties.
#include "../radiation/sampling.h"

namespace thermodec {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Area-preserving square -> triangle map (barycentric (1 - sqrt u, sqrt u (1 - v), sqrt u v)).
Eigen::Vector3d on_triangle(const Eigen::Vector2d& uv, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const double su = std::sqrt(uv.x());
  return (1.0 - su) * a + su * (1.0 - uv.y()) * b + su * uv.y() * c;
}

struct Side {
  Eigen::Vector3d a, b, c, normal;
  double area = 0.0;
  double offset = 0.0;  // ray-origin lift along the normal [m]
};

// Scrambling seeds of a side for one purpose: a pure function of (seed, side identity), so
// an unchanged face keeps its samples in a modified model and results ignore thread count.
std::array<std::uint32_t, 4> side_seeds(std::uint64_t seed, std::uint64_t key, std::uint64_t purpose) {
  std::array<std::uint32_t, 4> out;
  const std::uint64_t h = sampling::hash_combine(sampling::hash_combine(key, seed), 0x10ad5000ull + purpose);
  for (int d = 0; d < 4; ++d) out[d] = std::uint32_t(sampling::hash_combine(h, d) >> 32);
  return out;
}

double scrambled(std::uint32_t sobol, std::uint32_t seed) {
  return sampling::to_unit_float(sampling::owen_scramble(sobol, seed)) + 0.5 / 16777216.0;
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
  }
  return out;
}

void orthonormal_frame(const Eigen::Vector3d& n, Eigen::Vector3d& t, Eigen::Vector3d& u) {
  t = (std::abs(n.x()) > 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX()).cross(n).normalized();
  u = n.cross(t);
}

RayQuery make_ray(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_far) {
  RayQuery r;
  for (int i = 0; i < 3; ++i) r.origin[i] = float(o[i]), r.direction[i] = float(d[i]);
  r.t_near = 0.0f;
  r.t_far = float(std::min(t_far, 1e30));
  return r;
}

// Unblocked fraction of each side's sample points towards the direction `toward` (unit),
// for sides facing it; 0 for the others. A pilot of the first P Sobol points (P a power of 2:
// one per 1/P-area stratum of the Owen-scrambled net) decides fully lit or fully shadowed
// sides; only sides where the pilot disagrees trace all `rays`. note: a shadow that slips
// between all P pilot points is missed; it then covers well under 1/P of the face (measured on
// the sample: P = 16 left 0.6 W seed-to-seed differences on single nodes, P = 64 < 0.2 W).
Eigen::VectorXd sunlit_fraction(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                                const Eigen::Vector3d& toward, const Eigen::VectorXi& side_rays, int pilot_rays,
                                std::uint64_t seed, const std::vector<char>* todo = nullptr) {
  const int ns = sides.size();
  Eigen::VectorXd frac = Eigen::VectorXd::Zero(ns);
  const auto sobol = sampling::sobol_4d(ns ? std::max(side_rays.maxCoeff(), pilot_rays) : 1);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    std::vector<RayQuery> batch;
    std::vector<std::uint8_t> blocked;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0 || g.normal.dot(toward) <= 0.0 || (todo && !(*todo)[s])) continue;
      const auto sd = side_seeds(seed, sides.key[s], 1);
      const int rays = side_rays[s], pilot = std::max(1, std::min(rays, pilot_rays));
      auto trace = [&](int from, int to) {
        batch.clear();
        for (int k = from; k < to; ++k) {
          const Eigen::Vector2d uv(scrambled(sobol[k][0], sd[0]), scrambled(sobol[k][1], sd[1]));
          batch.push_back(make_ray(on_triangle(uv, g.a, g.b, g.c) + g.offset * g.normal, toward, 1e30));
        }
        scene.occluded(batch, blocked);
        int open = 0;
        for (auto b : blocked) open += !b;
        return open;
      };
      const int open_pilot = trace(0, pilot);
      if (open_pilot == 0 || open_pilot == pilot || pilot == rays) {
        frac[s] = double(open_pilot) / pilot;
      } else {
        frac[s] = double(open_pilot + trace(pilot, rays)) / rays;
      }
    }
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

// `rays` = #sides rays for a side whose view is partly blocked (the pilot decides).
EarthHits earth_hits(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                     const Eigen::Vector3d& earth_dir_in, double distance_m, const Eigen::VectorXi& side_rays,
                     int pilot_rays, std::uint64_t seed, const std::vector<char>* todo = nullptr, bool flatten = true) {
  const int ns = sides.size();
  EarthHits out;
  out.rays.resize(ns);
  out.view_factor = Eigen::VectorXd::Zero(ns);
  const auto sobol = sampling::sobol_4d(ns ? std::max(side_rays.maxCoeff(), pilot_rays) : 1);
  const Eigen::Vector3d earth_dir = earth_dir_in.normalized();
  const Eigen::Vector3d centre = earth_dir * distance_m;
  const double R2 = kEarthRadius_m * kEarthRadius_m;
  const double sin_half = kEarthRadius_m / distance_m;
  const double cos_half = std::sqrt(1.0 - sin_half * sin_half);
  const double cap_over_pi = 2.0 * (1.0 - cos_half);  // Omega_cap / pi
  Eigen::Vector3d et, eu;
  orthonormal_frame(earth_dir, et, eu);
  // Which sides may have their view of the Earth blocked at all: some other face's bounding
  // sphere meets the set of rays leaving the side's bounding sphere inside the Earth's cone
  // and in front of the side. The pilot alone would call a side unobstructed when a small
  // blocker slips between its pilot rays, a seed-dependent (heavy-tailed) error; with this
  // conservative geometric test such sides always trace all their rays.
  std::vector<Eigen::Vector3d> centre_of(ns);
  std::vector<double> radius_of(ns, 0.0);
  for (int s = 0; s < ns; ++s) {
    const Side& g = geo[s];
    centre_of[s] = (g.a + g.b + g.c) / 3.0;
    radius_of[s] = std::max({(g.a - centre_of[s]).norm(), (g.b - centre_of[s]).norm(), (g.c - centre_of[s]).norm()}) +
                   2.0 * g.offset + 1e-9;
  }
  const double half_angle = std::asin(sin_half);
  std::vector<char> may_be_blocked(ns, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      if (geo[s].area <= 0.0 || (todo && !(*todo)[s])) continue;
      for (int t = 0; t < ns && !may_be_blocked[s]; ++t) {
        if (sides.face[t] == sides.face[s] || geo[t].area <= 0.0) continue;
        const Eigen::Vector3d v = centre_of[t] - centre_of[s];
        const double reach = radius_of[s] + radius_of[t], dist = v.norm();
        if (v.dot(geo[s].normal) < -reach) continue;  // wholly behind the side
        if (dist <= reach) {
          may_be_blocked[s] = 1;
          continue;
        }
        const double angle = std::acos(std::clamp(v.dot(earth_dir) / dist, -1.0, 1.0));
        if (angle <= half_angle + std::asin(std::min(1.0, reach / dist)) + 1e-9) may_be_blocked[s] = 1;
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 32), [&](const tbb::blocked_range<int>& range) {
    std::vector<RayQuery> batch;
    std::vector<std::uint8_t> blocked;
    std::vector<std::pair<float, Eigen::Vector3f>> candidate;  // (cos theta, Earth normal)
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0) continue;
      if (g.normal.dot(earth_dir) <= -sin_half) continue;  // the whole Earth is below its horizon
      if (todo && !(*todo)[s]) continue;
      const auto sd = side_seeds(seed, sides.key[s], 2);
      const int rays = side_rays[s], pilot = std::max(1, std::min(rays, pilot_rays));
      batch.clear();
      candidate.clear();
      auto add_rays = [&](int from, int to) {
        for (int k = from; k < to; ++k) {
          const auto& q = sobol[k];
          const Eigen::Vector2d uv(scrambled(q[0], sd[0]), scrambled(q[1], sd[1]));
          const double cos_a = 1.0 - scrambled(q[2], sd[2]) * (1.0 - cos_half), phi = 2.0 * kPi * scrambled(q[3], sd[3]);
          const double sin_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a));
          const Eigen::Vector3d d = cos_a * earth_dir + sin_a * (std::cos(phi) * et + std::sin(phi) * eu);
          const double cos_t = g.normal.dot(d);
          if (cos_t <= 0.0) continue;
          const Eigen::Vector3d o = on_triangle(uv, g.a, g.b, g.c) + g.offset * g.normal;
          const Eigen::Vector3d oc = centre - o;
          const double tc = oc.dot(d);
          const double d2 = std::max(0.0, oc.squaredNorm() - tc * tc);
          const double t_hit = d2 < R2 ? tc - std::sqrt(R2 - d2) : tc;  // grazing: nearest point
          batch.push_back(make_ray(o, d, 1e30));
          candidate.emplace_back(float(cos_t), ((o + t_hit * d - centre).normalized()).cast<float>());
        }
      };
      // Pilot: a side none of whose first `pilot` rays is blocked and that no face can block
      // (may_be_blocked) sees the Earth unobstructed and keeps those (its view factor is the
      // closed form, the pilot rays serve the albedo lighting); a side
      // all of whose pilot rays are blocked (e.g. an internal wall) sees none of it; only sides
      // with both trace all `rays`, where the visibility edge needs them.
      add_rays(0, pilot);
      if (batch.empty()) continue;
      scene.occluded(batch, blocked);
      int used = pilot, n_blocked = 0;
      for (auto b : blocked) n_blocked += b != 0;
      const bool mixed = (n_blocked > 0 && n_blocked < static_cast<int>(blocked.size())) ||
                         (n_blocked == 0 && may_be_blocked[s]);
      if (mixed && rays > pilot) {
        const size_t first_new = batch.size();
        add_rays(pilot, rays);
        std::vector<std::uint8_t> more;
        std::vector<RayQuery> rest(batch.begin() + first_new, batch.end());
        if (!rest.empty()) scene.occluded(rest, more);
        blocked.insert(blocked.end(), more.begin(), more.end());
        used = rays;
      }
      // Ratio estimator: the unobstructed view factor has a closed form, only the blocked
      // share is left to the rays, F = F_open x (sum over unblocked rays of cos theta) / (sum
      // over all rays of cos theta). An unobstructed side is then exact and a partly blocked
      // one only carries the (correlated, hence much smaller) error of the ratio. The albedo
      // weights are scaled alike.
      double all = 0.0;
      for (size_t k = 0; k < batch.size(); ++k) all += candidate[k].first;
      const double f_open = unobstructed_earth_view_factor(g.normal.dot(earth_dir), distance_m);
      const double weight = all > 0.0 ? f_open / all : cap_over_pi / used;
      auto& keep = out.rays[s];
      double f = 0.0;
      for (size_t k = 0; k < batch.size(); ++k)
        if (!blocked[k]) {
          keep.emplace_back(float(weight * candidate[k].first), candidate[k].second);
          f += weight * candidate[k].first;
        }
      out.view_factor[s] = f;
    }
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
  int rays = 0;
};

std::vector<std::vector<Eigen::Vector3f>> escaping_directions(const RayScene& scene, const std::vector<Side>& geo,
                                                             const SurfaceSides& sides, int rays, std::uint64_t seed,
                                                             const std::vector<char>* todo) {
  const int ns = sides.size();
  const auto sobol = sampling::sobol_4d(rays);
  std::vector<std::vector<Eigen::Vector3f>> per_side(ns);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 32), [&](const tbb::blocked_range<int>& range) {
    std::vector<RayQuery> batch;
    std::vector<std::uint8_t> blocked;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0 || (todo && !(*todo)[s])) continue;
      Eigen::Vector3d t, u;
      orthonormal_frame(g.normal, t, u);
      const auto sd = side_seeds(seed, sides.key[s], 3);
      batch.clear();
      std::vector<Eigen::Vector3f> dirs;
      for (int k = 0; k < rays; ++k) {
        const auto& q = sobol[k];
        const Eigen::Vector2d uv(scrambled(q[0], sd[0]), scrambled(q[1], sd[1]));
        const double r2 = scrambled(q[2], sd[2]), phi = 2.0 * kPi * scrambled(q[3], sd[3]);
        const double st = std::sqrt(r2), ct = std::sqrt(std::max(0.0, 1.0 - r2));  // Malley
        const Eigen::Vector3d d = st * std::cos(phi) * t + st * std::sin(phi) * u + ct * g.normal;
        batch.push_back(make_ray(on_triangle(uv, g.a, g.b, g.c) + g.offset * g.normal, d, 1e30));
        dirs.push_back(d.cast<float>());
      }
      scene.occluded(batch, blocked);
      for (int k = 0; k < rays; ++k)
        if (!blocked[k]) per_side[s].push_back(dirs[k]);
    }
  });
  return per_side;
}

EscapingRays pack_escaping(const std::vector<std::vector<Eigen::Vector3f>>& per_side, int rays) {
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
  const double w = 1.0 / esc.rays;
  view_factor.setZero(ns);
  lit_sum.setZero(ns);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      double f = 0.0, lit = 0.0;
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
  const EarthHits hits = earth_hits(scene, geo, sides, earth_direction_body, distance_m,
                                    Eigen::VectorXi::Constant(sides.size(), rays), rays, seed);
  return hits.view_factor;
}

Loads external_loads(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
                     const FaceViewFactors* view_factors, const ExternalLoadSettings& settings,
                     const std::function<void(const std::string&)>& progress, LoadSamples* samples,
                     LoadReuse* reuse) {
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
  for (auto* m : {&loads.solar_W, &loads.albedo_W, &loads.earth_ir_W, &loads.reflected_solar_W})
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
  const Eigen::VectorXi sun_rays = rays_per_side_of_node(sides, settings.sun_rays_per_face, settings.sun_min_rays_per_node);
  const Eigen::VectorXi earth_rays =
      rays_per_side_of_node(sides, settings.earth_rays_per_face, settings.earth_min_rays_per_node);
  auto same_counts = [&](int s) {
    return ref_of[s] >= 0 && ref->sun_rays.size() == static_cast<Eigen::Index>(ref->key.size()) &&
           ref->sun_rays[ref_of[s]] == sun_rays[s] && ref->earth_rays[ref_of[s]] == earth_rays[s];
  };
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
  // Bounding sphere of each side (plus its ray lift) against the changed region's sphere.
  auto side_sphere = [&](int s, Eigen::Vector3d& c) {
    const Side& g = geo[s];
    c = (g.a + g.b + g.c) / 3.0;
    return std::max({(g.a - c).norm(), (g.b - c).norm(), (g.c - c).norm()}) + 2.0 * g.offset + 1e-9;
  };
  auto clear_of_change_along = [&](int s, const Eigen::Vector3d& d) {  // half-line family c + t d
    if (change_radius < 0.0) return true;
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    const Eigen::Vector3d bc = change_centre - c;
    const double t = std::max(0.0, bc.dot(d));
    return (bc - t * d).norm() > rho + change_radius;
  };
  auto clear_of_change_in_cone = [&](int s, const Eigen::Vector3d& axis, double half_angle) {
    if (change_radius < 0.0) return true;
    Eigen::Vector3d c;
    const double rho = side_sphere(s, c);
    const Eigen::Vector3d bc = change_centre - c;
    const double dist = bc.norm(), reach = rho + change_radius;
    if (dist <= reach) return false;
    const double angle = std::acos(std::clamp(bc.dot(axis) / dist, -1.0, 1.0));
    return angle > half_angle + std::asin(std::min(1.0, reach / dist)) + 1e-9;
  };
  auto clear_of_change_in_front = [&](int s) {
    if (change_radius < 0.0) return true;
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
  }

  // Solar-band incident power per side and step [W] (direct and albedo), absorbed shares.
  Eigen::MatrixXd incident_direct = Eigen::MatrixXd::Zero(ns, steps);
  Eigen::MatrixXd incident_albedo = Eigen::MatrixXd::Zero(ns, steps);

  // Direct sun: one shadow computation per distinct sun direction in body axes (a single one
  // for sun-pointing and inertial attitudes or a fixed sun).
  if (progress) progress("direct sun: " + std::to_string(steps) + " step(s)");
  Eigen::Vector3d last_dir = Eigen::Vector3d::Zero();
  Eigen::VectorXd lit;
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
      lit = sunlit_fraction(scene, geo, sides, st.sun_direction_body, sun_rays, settings.sun_pilot_rays, settings.seed, ref ? &todo : nullptr);
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!todo[s]) lit[s] = ref->sunlit(ref_of[s], k);
      last_dir = st.sun_direction_body;
    }
    if (samples) samples->sunlit.col(k) = lit;
    for (int s = 0; s < ns; ++s)
      incident_direct(s, k) = flux * geo[s].area * std::max(0.0, geo[s].normal.dot(st.sun_direction_body)) * lit[s];
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
    std::vector<char> earth_todo(ns, 1);
    if (ref)
      for (int s = 0; s < ns; ++s) {
        earth_todo[s] = !(same_counts(s) && (earth_fixed ? clear_of_change_in_cone(s, states[0].earth_direction_body.normalized(), half_angle)
                                                          : clear_of_change_in_front(s)));
        reuse->reused_earth += !earth_todo[s];
        reuse->total_earth += 1;
      }
    EarthHits hits;
    EscapingRays escaping;
    if (earth_fixed) {
      hits = earth_hits(scene, geo, sides, states[0].earth_direction_body, distance,
                        earth_rays, settings.earth_pilot_rays, settings.seed, ref ? &earth_todo : nullptr, /*flatten=*/false);
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!earth_todo[s]) {
            hits.rays[s] = ref->earth[ref_of[s]];
            hits.view_factor[s] = ref->earth_view_factor[ref_of[s]];
          }
      if (samples) {
        samples->earth = hits.rays;
        samples->earth_view_factor = hits.view_factor;
      }
      hits.flatten();
    } else {
      auto dirs = escaping_directions(scene, geo, sides, settings.earth_rays_per_face, settings.seed,
                                      ref ? &earth_todo : nullptr);
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!earth_todo[s]) {
            dirs[s].clear();
            for (const auto& [w, d] : ref->earth[ref_of[s]]) dirs[s].push_back(d);
          }
      if (samples)
        for (int s = 0; s < ns; ++s)
          for (const auto& d : dirs[s]) samples->earth[s].emplace_back(1.0f / settings.earth_rays_per_face, d);
      escaping = pack_escaping(dirs, settings.earth_rays_per_face);
    }
    Eigen::VectorXd view_factor, lit_sum(ns);
    for (int k = 0; k < steps; ++k) {
      const OrbitState& st = states[k];
      if (earth_fixed) {
        const float sx = float(st.sun_direction_body.x()), sy = float(st.sun_direction_body.y()),
                    sz = float(st.sun_direction_body.z());
        const float* nx = hits.normals.col(0).data();
        const float* ny = hits.normals.col(1).data();
        const float* nz = hits.normals.col(2).data();
        const float* w = hits.weights.data();
        tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
          for (int s = range.begin(); s < range.end(); ++s) {
            float sum = 0.0f;
            for (int k = hits.begin[s]; k < hits.begin[s + 1]; ++k)
              sum += w[k] * std::max(0.0f, nx[k] * sx + ny[k] * sy + nz[k] * sz);
            lit_sum[s] = sum;
          }
        });
        view_factor = hits.view_factor;
      } else {
        earth_view_from_escaping(escaping, st.earth_direction_body, distance, st.sun_direction_body, view_factor, lit_sum);
      }
      for (int s = 0; s < ns; ++s) {
        if (view_factor[s] == 0.0) continue;
        incident_albedo(s, k) = env.albedo * flux * geo[s].area * lit_sum[s];
        const int node = sides.node[s];
        if (node >= 0) loads.earth_ir_W(node, k) += eps[s] * env.earth_ir_flux_W_per_m2 * geo[s].area * view_factor[s];
      }
    }
  }

  if (samples) samples->earth_fixed = !orbit || [&] {
    for (int k = 1; k < steps; ++k)
      if (!same_direction(states[k].earth_direction_body, states[0].earth_direction_body)) return false;
    return true;
  }();

  for (int s = 0; s < ns; ++s) {
    const int node = sides.node[s];
    if (node < 0 || node >= num_nodes) continue;
    loads.solar_W.row(node) += alpha[s] * incident_direct.row(s);
    loads.albedo_W.row(node) += alpha[s] * incident_albedo.row(s);
  }

  if (settings.solar_reflections && view_factors) {
    if (progress) progress("solar reflections");
    if (view_factors->sides.size() != ns)
      throw InvalidInput("external loads: view factors are for " + std::to_string(view_factors->sides.size()) +
                         " sides, the model has " + std::to_string(ns));
    const GebhartFactors solar = gebhart_factors(*view_factors, alpha, node_groups(sides, num_nodes), num_nodes + 1);
    // A side receiving Q in the solar band absorbs alpha Q itself (counted above) and reflects
    // (1 - alpha) Q, of which node g finally absorbs the fraction B(s, g).
    const Eigen::MatrixXd incident = incident_direct + incident_albedo;
    for (int s = 0; s < ns; ++s) {
      if (incident.row(s).isZero()) continue;
      for (int g = 0; g < num_nodes; ++g)
        if (solar.B(s, g) != 0.0) loads.reflected_solar_W.row(g) += (1.0 - alpha[s]) * solar.B(s, g) * incident.row(s);
    }
  }
  return loads;
}

}  // namespace thermodec
