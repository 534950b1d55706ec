// External loads: direct sun with self-shadowing, Earth albedo and IR through ray-traced
// face-to-Earth view factors, and solar-band diffuse reflections (Gebhart with absorptivity).
// The paper (Sec. III) lists the three effects that make a face's incident solar power:
// its angle to the source, occlusion by other faces, and reflections from other faces.
#include "thermodec/environment/external_loads.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint64_t mix(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
double unit(std::uint64_t h) { return double(h >> 11) * (1.0 / 9007199254740992.0); }

// Counter-based stream: the i-th uniform of (seed, side identity, purpose) is a pure function
// of those, so every side's samples are independent of evaluation order and thread.
struct Stream {
  std::uint64_t base;
  Stream(std::uint64_t seed, std::uint64_t key, std::uint64_t purpose)
      : base(mix(mix(seed ^ 0x7468657266ull) ^ key) ^ mix(purpose)) {}
  double operator()(std::uint64_t i) const { return unit(mix(base + 0x632be59bd9b4e019ull * (i + 1))); }
};

// Jittered stratified samples in the unit square: m x m cells (m = ceil(sqrt(n))), the first n
// cells in a hashed order so n need not be a square.
std::vector<Eigen::Vector2d> stratified_square(int n, const Stream& rng, std::uint64_t offset) {
  const int m = static_cast<int>(std::ceil(std::sqrt(double(n))));
  std::vector<std::pair<std::uint64_t, int>> order(m * m);
  for (int c = 0; c < m * m; ++c) order[c] = {mix(rng.base ^ (offset + c)), c};
  if (n < m * m) std::sort(order.begin(), order.end());
  std::vector<Eigen::Vector2d> pts(n);
  for (int k = 0; k < n; ++k) {
    const int c = order[k].second;
    pts[k] = {((c % m) + rng(offset + 2 * k)) / m, ((c / m) + rng(offset + 2 * k + 1)) / m};
  }
  return pts;
}

// Area-preserving square -> triangle map (barycentric (1 - sqrt u, sqrt u (1 - v), sqrt u v)).
Eigen::Vector3d on_triangle(const Eigen::Vector2d& uv, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const double su = std::sqrt(uv.x());
  return (1.0 - su) * a + su * (1.0 - uv.y()) * b + su * uv.y() * c;
}

// Shirley-Chiu concentric map to the disk, lifted to the cosine-weighted hemisphere (Malley).
Eigen::Vector3d cosine_direction(const Eigen::Vector2d& uv) {
  const double a = 2.0 * uv.x() - 1.0, b = 2.0 * uv.y() - 1.0;
  double r, phi;
  if (a == 0.0 && b == 0.0) {
    r = 0.0, phi = 0.0;
  } else if (std::abs(a) > std::abs(b)) {
    r = a, phi = (kPi / 4) * (b / a);
  } else {
    r = b, phi = kPi / 2 - (kPi / 4) * (a / b);
  }
  const double x = r * std::cos(phi), y = r * std::sin(phi);
  return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}

struct Side {
  Eigen::Vector3d a, b, c, normal;
  double area = 0.0;
};

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

// Offset of ray origins along the side normal so a ray does not hit its own face.
double origin_offset(const RayScene& scene) {
  const auto& box = scene.bounds();
  const double diag = box.isEmpty() ? 1.0 : (box.max() - box.min()).norm();
  return std::max(1e-6 * diag, 1e-9);
}

// Unblocked fraction of each side's sample points towards the direction `toward` (unit),
// for sides facing it; 0 for the others.
Eigen::VectorXd sunlit_fraction(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                                const Eigen::Vector3d& toward, int rays, std::uint64_t seed) {
  const int ns = sides.size();
  Eigen::VectorXd frac = Eigen::VectorXd::Zero(ns);
  const double eps = origin_offset(scene);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    std::vector<RayQuery> batch;
    std::vector<std::uint8_t> blocked;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0 || g.normal.dot(toward) <= 0.0) continue;
      const Stream rng(seed, sides.key[s], 1);
      const auto pts = stratified_square(rays, rng, 0);
      batch.clear();
      for (const auto& uv : pts) batch.push_back(make_ray(on_triangle(uv, g.a, g.b, g.c) + eps * g.normal, toward, 1e30));
      scene.occluded(batch, blocked);
      int open = 0;
      for (auto b : blocked) open += !b;
      frac[s] = double(open) / rays;
    }
  });
  return frac;
}

// Earth rays of each side: normals (body axes) of the Earth points reached by unblocked rays.
struct EarthHits {
  std::vector<std::vector<Eigen::Vector3f>> normals;  // per side
  int rays = 0;
};

EarthHits earth_hits(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                     const Eigen::Vector3d& earth_dir, double distance_m, int rays, std::uint64_t seed) {
  const int ns = sides.size();
  EarthHits out;
  out.rays = rays;
  out.normals.resize(ns);
  const double eps = origin_offset(scene);
  const Eigen::Vector3d centre = earth_dir.normalized() * distance_m;
  const double R2 = kEarthRadius_m * kEarthRadius_m;
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 32), [&](const tbb::blocked_range<int>& range) {
    std::vector<RayQuery> batch;
    std::vector<std::uint8_t> blocked;
    std::vector<Eigen::Vector3f> hit_normal;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0) continue;
      // Skip sides that cannot see any of the Earth: the Earth cap lies beyond their horizon.
      const double sin_half = kEarthRadius_m / distance_m;
      if (g.normal.dot(earth_dir) <= -sin_half) continue;
      Eigen::Vector3d t, u;
      orthonormal_frame(g.normal, t, u);
      const Stream rng(seed, sides.key[s], 2);
      const auto dirs = stratified_square(rays, rng, 0);
      const auto pts = stratified_square(rays, rng, 0x100000000ull);
      batch.clear();
      hit_normal.clear();
      for (int k = 0; k < rays; ++k) {
        const Eigen::Vector3d l = cosine_direction(dirs[k]);
        const Eigen::Vector3d d = l.x() * t + l.y() * u + l.z() * g.normal;
        // Decorrelate origin and direction strata by pairing direction k with point k' (hashed).
        const Eigen::Vector3d o = on_triangle(pts[(k * 7919 + (rng.base & 0xffff)) % rays], g.a, g.b, g.c) + eps * g.normal;
        const Eigen::Vector3d oc = centre - o;
        const double tc = oc.dot(d);
        if (tc <= 0.0) continue;
        const double d2 = oc.squaredNorm() - tc * tc;
        if (d2 >= R2) continue;
        const double t_hit = tc - std::sqrt(R2 - d2);
        batch.push_back(make_ray(o, d, 1e30));
        hit_normal.push_back(((o + t_hit * d - centre) / kEarthRadius_m).cast<float>());
      }
      if (batch.empty()) continue;
      scene.occluded(batch, blocked);
      auto& keep = out.normals[s];
      for (size_t k = 0; k < batch.size(); ++k)
        if (!blocked[k]) keep.push_back(hit_normal[k]);
    }
  });
  return out;
}

bool same_direction(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm() < 1e-12; }

}  // namespace

Eigen::VectorXd earth_view_factors(const RayScene& scene, const SurfaceSides& sides,
                                   const Eigen::Vector3d& earth_direction_body, double distance_m, int rays,
                                   std::uint64_t seed) {
  if (rays < 1) throw InvalidInput("earth_rays_per_face must be >= 1");
  if (!(distance_m > kEarthRadius_m)) throw InvalidInput("Earth view factors: distance must exceed the Earth radius");
  const auto geo = side_geometry(scene.mesh(), sides);
  const EarthHits hits = earth_hits(scene, geo, sides, earth_direction_body, distance_m, rays, seed);
  Eigen::VectorXd F(sides.size());
  for (int s = 0; s < sides.size(); ++s) F[s] = double(hits.normals[s].size()) / rays;
  return F;
}

Loads external_loads(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
                     const FaceViewFactors* view_factors, const ExternalLoadSettings& settings,
                     const std::function<void(const std::string&)>& progress) {
  const Environment& env = model.environment;
  if (settings.sun_rays_per_face < 1) throw InvalidInput("sun_rays_per_face must be >= 1");
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

  // Solar-band incident power per side and step [W] (direct and albedo), absorbed shares.
  Eigen::MatrixXd incident_direct = Eigen::MatrixXd::Zero(ns, steps);
  Eigen::MatrixXd incident_albedo = Eigen::MatrixXd::Zero(ns, steps);

  // Direct sun: one shadow computation per distinct sun direction in body axes (a single one
  // for sun-pointing and inertial attitudes or a fixed sun).
  if (progress) progress("direct sun: " + std::to_string(steps) + " step(s)");
  Eigen::Vector3d last_dir = Eigen::Vector3d::Zero();
  Eigen::VectorXd lit;
  for (int k = 0; k < steps; ++k) {
    const OrbitState& st = states[k];
    loads.in_shadow[k] = st.in_shadow;
    if (st.in_shadow || flux == 0.0) continue;
    if (lit.size() == 0 || !same_direction(st.sun_direction_body, last_dir)) {
      lit = sunlit_fraction(scene, geo, sides, st.sun_direction_body, settings.sun_rays_per_face, settings.seed);
      last_dir = st.sun_direction_body;
    }
    for (int s = 0; s < ns; ++s)
      incident_direct(s, k) = flux * geo[s].area * std::max(0.0, geo[s].normal.dot(st.sun_direction_body)) * lit[s];
  }

  // Earth: view rays once per distinct Earth direction (once for a nadir attitude).
  if (orbit) {
    if (progress) progress("Earth view factors");
    const double distance = orbit_radius_m(env.altitude_km);
    EarthHits hits;
    Eigen::Vector3d last_earth = Eigen::Vector3d::Zero();
    for (int k = 0; k < steps; ++k) {
      const OrbitState& st = states[k];
      if (hits.normals.empty() || !same_direction(st.earth_direction_body, last_earth)) {
        hits = earth_hits(scene, geo, sides, st.earth_direction_body, distance, settings.earth_rays_per_face,
                          settings.seed);
        last_earth = st.earth_direction_body;
      }
      const Eigen::Vector3f sun = st.sun_direction_body.cast<float>();
      for (int s = 0; s < ns; ++s) {
        const auto& normals = hits.normals[s];
        if (normals.empty()) continue;
        const int node = sides.node[s];
        const double f_earth = double(normals.size()) / hits.rays;
        double lit_sum = 0.0;
        for (const auto& n : normals) lit_sum += std::max(0.0f, n.dot(sun));
        incident_albedo(s, k) = env.albedo * flux * geo[s].area * lit_sum / hits.rays;
        if (node >= 0) loads.earth_ir_W(node, k) += eps[s] * env.earth_ir_flux_W_per_m2 * geo[s].area * f_earth;
      }
    }
  }

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
