// Radiative engine benchmark: one line per case.
//   - thermodec's view-factor tracing rate (ray generation + Embree + hit bookkeeping) vs a
//     bare Embree loop (rtcIntersect1 over pre-generated rays, same scene flags, same ray
//     count and distribution) on the same scene in the same run, and their ratio;
//   - incremental (one node changed) vs full recompute of the node couplings;
//   - external-geometry extraction time.
// Models: the sample satellite (coarse ~1k faces, dense ~20k), and the dense one subdivided
// 1 -> 4 (~79k faces). Fixed seeds; never a pass/fail.
#include <embree3/rtcore.h>
#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <map>
#include <filesystem>
#include <random>
#include <thread>

#include <sys/resource.h>

#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/external_geometry.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/radiation_reference.h"
#include "thermodec/radiation/radiative_couplings.h"

using namespace thermodec;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU time of the whole process (all threads) [s]. On a machine shared with other jobs the
// wall-clock rate swings with their load; CPU time charges each loop only for the cycles it
// actually got, so the ratio below is taken on CPU time.
double cpu_seconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// 1 -> 4 midpoint subdivision, attributes copied to the children.
ThermalModel subdivided(const ThermalModel& m) {
  ThermalModel out = m;
  const Mesh& a = m.mesh;
  Mesh& b = out.mesh;
  std::vector<Eigen::RowVector3d> V;
  for (int v = 0; v < a.num_vertices(); ++v) V.push_back(a.V.row(v));
  std::map<std::pair<int, int>, int> mid;
  auto midpoint = [&](int i, int j) {
    const auto key = std::minmax(i, j);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    V.push_back(0.5 * (a.V.row(i) + a.V.row(j)));
    return mid[key] = static_cast<int>(V.size()) - 1;
  };
  const int nf = a.num_faces();
  b.F.resize(4 * nf, 3);
  b.face_node.resize(4 * nf);
  b.face_material.resize(4 * nf);
  b.face_back_material.resize(4 * nf);
  for (int f = 0; f < nf; ++f) {
    const int x = a.F(f, 0), y = a.F(f, 1), z = a.F(f, 2);
    const int xy = midpoint(x, y), yz = midpoint(y, z), zx = midpoint(z, x);
    const int tris[4][3] = {{x, xy, zx}, {xy, y, yz}, {zx, yz, z}, {xy, yz, zx}};
    for (int k = 0; k < 4; ++k) {
      b.F.row(4 * f + k) << tris[k][0], tris[k][1], tris[k][2];
      b.face_node[4 * f + k] = a.face_node[f];
      b.face_material[4 * f + k] = a.face_material[f];
      b.face_back_material[4 * f + k] = a.face_back_material[f];
    }
  }
  b.V.resize(V.size(), 3);
  for (std::size_t v = 0; v < V.size(); ++v) b.V.row(v) = V[v];
  return out;
}

// Synthetic stand-in if the sample satellite is missing: box body + two panels (grids).
ThermalModel synthetic(int n) {
  ThermalModel m;
  Mesh& mesh = m.mesh;
  std::vector<Eigen::RowVector3d> V;
  std::vector<Eigen::RowVector3i> F;
  std::vector<int> node;
  auto quad_grid = [&](Eigen::RowVector3d c, Eigen::RowVector3d u, Eigen::RowVector3d v, int nd) {
    const int v0 = static_cast<int>(V.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) V.push_back(c + u * (double(i) / n) + v * (double(j) / n));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int a = v0 + i * (n + 1) + j, b = a + n + 1;
        F.emplace_back(a, b, b + 1);
        F.emplace_back(a, b + 1, a + 1);
        node.push_back(nd);
        node.push_back(nd);
      }
  };
  quad_grid({-.5, -.5, -.5}, {0, 1, 0}, {1, 0, 0}, 0);
  quad_grid({-.5, -.5, .5}, {1, 0, 0}, {0, 1, 0}, 0);
  quad_grid({-.5, -.5, -.5}, {1, 0, 0}, {0, 0, 1}, 0);
  quad_grid({-.5, .5, -.5}, {0, 0, 1}, {1, 0, 0}, 0);
  quad_grid({-.5, -.5, -.5}, {0, 0, 1}, {0, 1, 0}, 0);
  quad_grid({.5, -.5, -.5}, {0, 1, 0}, {0, 0, 1}, 0);
  quad_grid({-.5, .8, 0}, {1, 0, 0}, {0, 2, 0}, 1);
  quad_grid({-.5, -2.8, 0}, {1, 0, 0}, {0, 2, 0}, 2);
  mesh.V.resize(V.size(), 3);
  for (std::size_t i = 0; i < V.size(); ++i) mesh.V.row(i) = V[i];
  mesh.F.resize(F.size(), 3);
  for (std::size_t i = 0; i < F.size(); ++i) mesh.F.row(i) = F[i];
  mesh.face_node = Eigen::Map<Eigen::VectorXi>(node.data(), node.size());
  mesh.face_material = Eigen::VectorXi::Zero(F.size());
  mesh.face_back_material = Eigen::VectorXi::Constant(F.size(), -1);
  for (std::size_t f = 0; f < F.size(); ++f)
    if (node[f] > 0) mesh.face_back_material[f] = 0;
  mesh.node_names = {"body", "wing_py", "wing_my"};
  mesh.material_names = {"paint"};
  m.materials = {Material{"paint", 0.3, 0.8}};
  for (const auto& nm : mesh.node_names) m.nodes.push_back(Node{nm, 0});
  return m;
}

// The bare loop: its own Embree scene (robust, high quality, like RayScene) and rays drawn
// beforehand with the same distribution (uniform on faces, cosine-weighted, lifted by 1e-5)
// and in the same order (side by side, backs of two-sided faces included).
struct Rate {
  double wall = 0;  // rays per wall-clock second
  double cpu = 0;   // rays per CPU second (all threads)
};

Rate bare_embree_rays_per_second(const Mesh& mesh, const SurfaceSides& sides, std::int64_t num_rays) {
  RTCDevice dev = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(dev);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, mesh.num_vertices()));
  for (int v = 0; v < mesh.num_vertices(); ++v)
    for (int k = 0; k < 3; ++k) vb[3 * v + k] = float(mesh.V(v, k));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, mesh.num_faces()));
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) ib[3 * f + k] = unsigned(mesh.F(f, k));
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);

  const std::int64_t n = std::min<std::int64_t>(num_rays, 8'000'000);  // memory cap; rate is what matters
  std::vector<float> org(3 * n), dir(3 * n);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  // Same order as thermodec traces them: face by face, so both loops see the same coherence.
  for (std::int64_t r = 0; r < n; ++r) {
    const int side = int(r * sides.size() / n);  // the same sides (fronts and backs) as thermodec
    const int f = sides.face[side];
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    Eigen::Vector3d nrm = (b - a).cross(c - a).normalized();
    if (sides.is_back[side]) nrm = -nrm;
    const double s = std::sqrt(U(rng)), t = U(rng);
    const Eigen::Vector3d p = a + (b - a) * (s * (1 - t)) + (c - a) * (s * t) + nrm * 1e-5;
    const Eigen::Vector3d tg = nrm.unitOrthogonal(), bt = nrm.cross(tg);
    const double u3 = U(rng), phi = 2 * M_PI * U(rng);
    const Eigen::Vector3d d = tg * (std::sqrt(u3) * std::cos(phi)) + bt * (std::sqrt(u3) * std::sin(phi)) + nrm * std::sqrt(1 - u3);
    for (int k = 0; k < 3; ++k) {
      org[3 * r + k] = float(p[k]);
      dir[3 * r + k] = float(d[k]);
    }
  }
  std::vector<int> hit(n);
  const double c0 = cpu_seconds();
  const auto t0 = Clock::now();
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, n, 4096), [&](const tbb::blocked_range<std::int64_t>& r) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::int64_t i = r.begin(); i != r.end(); ++i) {
      RTCRayHit rh;
      rh.ray.org_x = org[3 * i]; rh.ray.org_y = org[3 * i + 1]; rh.ray.org_z = org[3 * i + 2];
      rh.ray.dir_x = dir[3 * i]; rh.ray.dir_y = dir[3 * i + 1]; rh.ray.dir_z = dir[3 * i + 2];
      rh.ray.tnear = 0; rh.ray.tfar = 3e38f; rh.ray.time = 0; rh.ray.mask = ~0u; rh.ray.id = 0; rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      hit[i] = int(rh.hit.primID);
    }
  });
  const double s = seconds_since(t0), c = cpu_seconds() - c0;
  rtcReleaseScene(scene);
  rtcReleaseDevice(dev);
  return {n / s, n / c};
}

void trace_case(const std::string& name, const ThermalModel& model, int rays) {
  RadiationSettings settings{rays, 1};
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  // Alternate the two measurements three times and keep each one's best, so a neighbour's
  // load spike hits both alike.
  Rate td, bare;
  for (int rep = 0; rep < 3; ++rep) {
    const double c0 = cpu_seconds();
    const auto t0 = Clock::now();
    const FaceViewFactors vf = face_view_factors(scene, sides, settings);
    const double s = seconds_since(t0), c = cpu_seconds() - c0;
    td.wall = std::max(td.wall, vf.rays_traced / s);
    td.cpu = std::max(td.cpu, vf.rays_traced / c);
    const Rate b = bare_embree_rays_per_second(model.mesh, sides, vf.rays_traced);
    bare.wall = std::max(bare.wall, b.wall);
    bare.cpu = std::max(bare.cpu, b.cpu);
  }
  const auto t1 = Clock::now();
  const NodeCouplings c = radiative_couplings(model, settings);
  const double total = seconds_since(t1);
  fmt::print("{:<24} {:>7} faces {:>6} sides x {:>5} rays: thermodec {:6.2f} Mrays/CPU-s ({:6.2f} Mrays/s wall), "
             "bare Embree {:6.2f} Mrays/CPU-s ({:6.2f} wall), ratio {:.2f} (wall {:.2f}); full couplings {:.2f} s "
             "({} Gebhart sweeps)\n",
             name, model.mesh.num_faces(), sides.size(), rays, td.cpu * 1e-6, td.wall * 1e-6, bare.cpu * 1e-6,
             bare.wall * 1e-6, td.cpu / bare.cpu, td.wall / bare.wall, total, c.diagnostics.gebhart_iterations);
}

void incremental_case(const std::string& name, const ThermalModel& model, int rays, const std::string& node_name) {
  RadiationSettings settings{rays, 1};
  int node = -1;
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (model.nodes[i].name == node_name) node = int(i);
  if (node < 0) node = int(model.nodes.size()) - 1;
  // Candidate: the node's vertices moved 2 mm along +z (a "decimated" node stand-in: its faces
  // all change identity; faces sharing its vertices change too).
  ThermalModel cand = model;
  std::vector<char> moved(model.mesh.num_vertices(), 0);
  for (int f = 0; f < model.mesh.num_faces(); ++f)
    if (model.mesh.face_node[f] == node)
      for (int k = 0; k < 3; ++k) moved[model.mesh.F(f, k)] = 1;
  for (int v = 0; v < model.mesh.num_vertices(); ++v)
    if (moved[v]) cand.mesh.V(v, 2) += 0.002;
  auto t0 = Clock::now();
  const RadiationReference ref = prepare_radiation(model, settings);
  const double prep = seconds_since(t0);
  t0 = Clock::now();
  IncrementalStats st;
  const NodeCouplings inc = radiative_couplings_incremental(ref, cand, &st);
  const double t_inc = seconds_since(t0);
  t0 = Clock::now();
  const NodeCouplings full = radiative_couplings(cand, settings);
  const double t_full = seconds_since(t0);
  const double max_diff = (inc.radiative_couplings_m2 - full.radiative_couplings_m2).cwiseAbs().maxCoeff();
  fmt::print("{:<24} node '{}' moved: prepare {:.2f} s, incremental {:.3f} s vs full {:.2f} s: speed-up {:.1f}x; "
             "{:.1f}% of rays re-traced; max |GR_inc - GR_full| {:.1e} m2, F identical: {}\n",
             name, model.nodes[node].name, prep, t_inc, t_full, t_full / t_inc,
             100.0 * st.rays_retraced / double(st.rays_total), max_diff,
             inc.view_factors == full.view_factors ? "yes" : "no");
}

// ~100k faces with a hidden interior: an outer closed box (80 x 80 quads per wall), an inner
// box (40 x 40) and an internal partition inside it: 19.2k faces should be dropped.
Mesh nested_boxes_100k() {
  Mesh m;
  std::vector<Eigen::RowVector3d> V;
  std::vector<Eigen::RowVector3i> F;
  std::vector<int> node;
  auto quad_grid = [&](Eigen::RowVector3d c, Eigen::RowVector3d u, Eigen::RowVector3d v, int n, int nd) {
    const int v0 = static_cast<int>(V.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) V.push_back(c + u * (double(i) / n) + v * (double(j) / n));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int a = v0 + i * (n + 1) + j, b = a + n + 1;
        F.emplace_back(a, b, b + 1);
        F.emplace_back(a, b + 1, a + 1);
        node.push_back(nd);
        node.push_back(nd);
      }
  };
  auto box = [&](double h, int n, int nd) {
    const Eigen::RowVector3d lo(-h, -h, -h), ex(2 * h, 0, 0), ey(0, 2 * h, 0), ez(0, 0, 2 * h);
    quad_grid(lo, ey, ex, n, nd);
    quad_grid(lo + ez, ex, ey, n, nd);
    quad_grid(lo, ex, ez, n, nd);
    quad_grid(lo + ey, ez, ex, n, nd);
    quad_grid(lo, ez, ey, n, nd);
    quad_grid(lo + ex, ey, ez, n, nd);
  };
  box(1.0, 80, 0);
  box(0.5, 40, 1);
  quad_grid({-0.9, 0.7, -0.9}, {1.8, 0, 0}, {0, 0, 1.8}, 20, 2);
  m.V.resize(V.size(), 3);
  for (std::size_t i = 0; i < V.size(); ++i) m.V.row(i) = V[i];
  m.F.resize(F.size(), 3);
  for (std::size_t i = 0; i < F.size(); ++i) m.F.row(i) = F[i];
  m.face_node = Eigen::Map<Eigen::VectorXi>(node.data(), node.size());
  m.face_material = Eigen::VectorXi::Zero(F.size());
  m.face_back_material = Eigen::VectorXi::Constant(F.size(), -1);
  m.node_names = {"outer", "inner", "partition"};
  m.material_names = {"paint"};
  return m;
}

void external_case(const std::string& name, const ThermalModel& model) {
  const auto t0 = Clock::now();
  const RayScene scene(model.mesh);
  const double build = seconds_since(t0);
  const ExternalFaces ext = external_faces(scene);
  const double total = seconds_since(t0);
  fmt::print("{:<24} {:>7} faces: external extraction {:.2f} s (scene build {:.2f} s), kept {}, dropped {}, {} rays\n",
             name, model.mesh.num_faces(), total, build, ext.kept, ext.dropped, ext.rays_traced);
}

}  // namespace

int main(int argc, char** argv) {
  // Optional argument: only the cases whose kind (trace, incremental, external) is given.
  const std::string only = argc > 1 ? argv[1] : "";
  auto want = [&](const char* kind) { return only.empty() || only == kind; };
  const std::filesystem::path dir = std::filesystem::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite";
  ThermalModel coarse, dense;
  std::string coarse_name = "satellite", dense_name = "satellite_dense";
  if (std::filesystem::exists(dir / "model.json") && std::filesystem::exists(dir / "model_dense.json")) {
    coarse = load_model(dir / "model.json");
    dense = load_model(dir / "model_dense.json");
  } else {
    coarse = synthetic(11);  // ~1.1k faces
    dense = synthetic(50);   // ~20k faces
    coarse_name = "synthetic_1k";
    dense_name = "synthetic_20k";
  }
  const ThermalModel big = subdivided(dense);
  fmt::print("hardware threads: {}\n", std::thread::hardware_concurrency());
  if (want("trace")) {
    trace_case(coarse_name, coarse, 4000);
    trace_case(dense_name, dense, 400);
    trace_case(dense_name + "_x4", big, 64);
  }
  if (want("incremental")) {
    incremental_case(coarse_name, coarse, 4000, "dish");
    incremental_case(coarse_name, coarse, 4000, "instrument");
    incremental_case(coarse_name, coarse, 4000, "yoke_py");
    incremental_case(dense_name, dense, 400, "instrument");
  }
  if (want("external")) {
    external_case(dense_name, dense);
    external_case(dense_name + "_x4", big);
    ThermalModel nested;
    nested.mesh = nested_boxes_100k();
    external_case("nested_boxes_100k", nested);
  }
  return 0;
}
