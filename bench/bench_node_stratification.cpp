// Measurement for an open sampling question ("a stratification
// that keeps faces' samples stable under local remeshing"; figures in docs/benchmarks.md): how much Monte Carlo scatter of a
// node's view factors is lost because every face side draws its own, independent scrambled
// Sobol set?
//
//   bench_node_stratification [MODEL] [rays per node side-set (default 250000)] [seeds (16)]
//
// For each node's fronts (and backs, if two-sided) it estimates the node-level view factors
// F(node -> every node, space) = sum_s A_s F_s / sum_s A_s with the same total ray count by
//  A. per face side: N_s = N A_s / A_node rays from the side's own Owen-scrambled 4-D Sobol set
//     (the engine's scheme, rays/sampling.h);
//  B. per node: ONE Owen-scrambled 4-D Sobol set over the node's sides projected on the
//     coordinate plane their normals are closest to (one set per axis direction, +x ... -z) (dims 1-2: position in that plane's box,
//     kept by the side whose projected triangle contains it; dims 3-4: cosine-weighted
//     direction in that side's frame), F_s = hits / rays that landed on s.
// and prints, per node side-set, the standard deviation over seeds of F to space and the
// largest standard deviation among its couplings, for A and B, and their ratio (> 1: the node-
// level set scatters less). Scheme B's set depends on the node's projected box, so it is not
// yet stable under decimation; this measures what such a scheme would be worth.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "thermodec/rays/sampling.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/surface_sides.h"

using namespace thermodec;

namespace {

struct SideGeom {
  int s;
  Eigen::Vector3d a, b, c, n;
  double area;
  int axis;  // coordinate axis the normal is closest to
};

// Target of a ray: node index of the hit face, or num_nodes for space.
void trace(const RayScene& scene, const Mesh& mesh, int num_nodes, std::vector<RayQuery>& rays,
           std::vector<int>& target) {
  std::vector<int> face;
  scene.intersect(rays, face);
  target.resize(rays.size());
  for (size_t i = 0; i < rays.size(); ++i)
    target[i] = face[i] < 0 ? num_nodes : std::max(0, std::min(num_nodes - 1, int(mesh.face_node[face[i]])));
}

bool in_triangle_2d(double px, double py, const double* ax, const double* ay) {
  double d[3];
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    d[k] = (ax[j] - ax[k]) * (py - ay[k]) - (ay[j] - ay[k]) * (px - ax[k]);
  }
  return (d[0] >= 0 && d[1] >= 0 && d[2] >= 0) || (d[0] <= 0 && d[1] <= 0 && d[2] <= 0);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json";
  const int rays_per_set = argc > 2 ? std::atoi(argv[2]) : 250000;
  const int seeds = argc > 3 ? std::atoi(argv[3]) : 16;
  const ThermalModel model = load_model(path);
  const Mesh& mesh = model.mesh;
  const int nn = static_cast<int>(model.nodes.size());
  const SurfaceSides sides = surface_sides(model);
  const RayScene scene(mesh);
  const int npts = 1 << int(std::ceil(std::log2(double(rays_per_set) * 4.0)));  // B: box > projected area
  const auto sobol = sampling::sobol_4d_reversed(npts);

  std::map<std::pair<int, int>, std::vector<SideGeom>> sets;  // (node, is_back) -> sides
  for (int s = 0; s < sides.size(); ++s) {
    const int f = sides.face[s];
    if (sides.node[s] < 0 || !is_traceable_face(mesh, f)) continue;
    SideGeom g;
    g.s = s;
    g.a = mesh.V.row(mesh.F(f, 0));
    g.b = mesh.V.row(mesh.F(f, 1));
    g.c = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d cr = (g.b - g.a).cross(g.c - g.a);
    g.area = 0.5 * cr.norm();
    g.n = cr.normalized() * (sides.is_back[s] ? -1.0 : 1.0);
    g.n.cwiseAbs().maxCoeff(&g.axis);
    sets[{sides.node[s], sides.is_back[s]}].push_back(g);
  }

  std::printf("%s: %d faces, %d nodes; %d rays per node side-set, %d seeds\n", path.c_str(), int(mesh.F.rows()), nn,
              rays_per_set, seeds);
  std::printf("%-14s %5s | %-23s | %-23s | %s\n", "node side-set", "sides", "A per side: sd(space) max", "B per node: sd(space) max",
              "gain space / max");
  double log_gain = 0.0;
  int n_gain = 0;
  for (const auto& [key, geo] : sets) {
    double area = 0.0;
    for (const auto& g : geo) area += g.area;
    std::vector<Eigen::VectorXd> FA, FB;
    std::vector<RayQuery> rays;
    std::vector<int> owner, target;
    std::vector<double> weight;
    for (int seed = 1; seed <= seeds; ++seed) {
      // A: independent set per side.
      rays.clear();
      owner.clear();
      for (size_t i = 0; i < geo.size(); ++i) {
        const auto& g = geo[i];
        const int n = std::max(1, int(std::lround(rays_per_set * g.area / area)));
        const auto e = sampling::make_emitter(g.a, g.b, g.c, sides.is_back[g.s] != 0,
                                              sampling::hash_combine(sides.key[g.s], std::uint64_t(seed)));
        for (int k = 0; k < n; ++k) {
          RayQuery q;
          sampling::emit(e, sobol[k], /*cosine=*/true, q.origin, q.direction);
          rays.push_back(q);
          owner.push_back(int(i));
        }
      }
      trace(scene, mesh, nn, rays, target);
      std::vector<int> count(geo.size(), 0);
      for (int o : owner) ++count[o];
      Eigen::VectorXd F = Eigen::VectorXd::Zero(nn + 1);
      for (size_t r = 0; r < rays.size(); ++r) F[target[r]] += geo[owner[r]].area / (area * count[owner[r]]);
      FA.push_back(F);

      // B: one set per (axis) over the projected box of the sides closest to that axis.
      rays.clear();
      owner.clear();
      for (int group = 0; group < 6; ++group) {
        const int axis = group / 2, sign = group % 2 ? -1 : 1;  // sides facing +axis or -axis
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        std::vector<int> members;
        Eigen::AlignedBox2d box;
        double proj_area = 0.0;
        for (size_t i = 0; i < geo.size(); ++i)
          if (geo[i].axis == axis && (geo[i].n[axis] > 0) == (sign > 0)) {
            members.push_back(int(i));
            for (const auto* p : {&geo[i].a, &geo[i].b, &geo[i].c}) box.extend(Eigen::Vector2d((*p)[u], (*p)[v]));
            proj_area += geo[i].area * std::abs(geo[i].n[axis]);
          }
        if (members.empty()) continue;
        double set_area = 0.0;
        for (int i : members) set_area += geo[i].area;
        const Eigen::Vector2d lo = box.min(), ext = box.sizes().cwiseMax(1e-12);
        // points in the box so that ~rays_per_set x set_area / area land on the sides
        const double want = rays_per_set * set_area / area;
        const int P = std::min(npts, std::max(1, int(std::lround(want * ext.x() * ext.y() / std::max(proj_area, 1e-300)))));
        std::uint32_t sd[4];
        const std::uint64_t k0 = sampling::hash_combine(sampling::hash_combine(std::uint64_t(key.first) * 7 + key.second, group), seed);
        for (int d = 0; d < 4; ++d) sd[d] = std::uint32_t(sampling::hash_combine(k0, 0x5eed0000ull + d) >> 32);
        for (int k = 0; k < P; ++k) {
          float x[4];
          for (int d = 0; d < 4; ++d)
            x[d] = sampling::to_unit_float(sampling::reverse_bits(sampling::laine_karras(sobol[k][d], sd[d])));
          const double pu = lo.x() + x[0] * ext.x(), pv = lo.y() + x[1] * ext.y();
          for (int i : members) {
            const auto& g = geo[i];
            const double au[3] = {g.a[u], g.b[u], g.c[u]}, av[3] = {g.a[v], g.b[v], g.c[v]};
            if (!in_triangle_2d(pu, pv, au, av)) continue;
            // lift onto the side's plane along the axis
            Eigen::Vector3d p;
            p[u] = pu;
            p[v] = pv;
            p[axis] = g.a[axis] - (g.n[u] * (pu - g.a[u]) + g.n[v] * (pv - g.a[v])) / g.n[axis];
            Eigen::Vector3d t, bt;
            sampling::basis(g.n, t, bt);
            const double st = std::sqrt(x[2]), ct = std::sqrt(std::max(0.0, 1.0 - x[2]));
            const double ph = 2.0 * M_PI * x[3];
            const Eigen::Vector3d d = t * st * std::cos(ph) + bt * st * std::sin(ph) + g.n * ct;
            const double mag = std::max({g.a.cwiseAbs().maxCoeff(), g.b.cwiseAbs().maxCoeff(), g.c.cwiseAbs().maxCoeff()});
            const Eigen::Vector3d o = p + g.n * (1e-5 * mag);
            RayQuery q;
            for (int c = 0; c < 3; ++c) {
              q.origin[c] = float(o[c]);
              q.direction[c] = float(d[c]);
            }
            rays.push_back(q);
            owner.push_back(i);
            break;
          }
        }
      }
      trace(scene, mesh, nn, rays, target);
      std::fill(count.begin(), count.end(), 0);
      for (int o : owner) ++count[o];
      F.setZero();
      double covered = 0.0;
      for (size_t i = 0; i < geo.size(); ++i)
        if (count[i] == 0) covered += geo[i].area;  // a side no point landed on: counted as in A below
      for (size_t r = 0; r < rays.size(); ++r) F[target[r]] += geo[owner[r]].area / (area * count[owner[r]]);
      if (covered > 0.0) F *= area / (area - covered);  // rare: tiny sides missed by every point
      FB.push_back(F);
    }
    auto stats = [&](const std::vector<Eigen::VectorXd>& Fs, double& sd_space, double& sd_max) {
      Eigen::VectorXd mean = Eigen::VectorXd::Zero(nn + 1), var = Eigen::VectorXd::Zero(nn + 1);
      for (const auto& F : Fs) mean += F;
      mean /= double(Fs.size());
      for (const auto& F : Fs) var += (F - mean).cwiseAbs2();
      var /= double(Fs.size() - 1);
      sd_space = std::sqrt(var[nn]);
      sd_max = std::sqrt(var.maxCoeff());
    };
    double a_space, a_max, b_space, b_max;
    stats(FA, a_space, a_max);
    stats(FB, b_space, b_max);
    // bias check: largest difference of the two means, in standard errors of that difference
    Eigen::VectorXd ma = Eigen::VectorXd::Zero(nn + 1), mb = ma;
    for (const auto& F : FA) ma += F / double(seeds);
    for (const auto& F : FB) mb += F / double(seeds);
    const double z = (ma - mb).cwiseAbs().maxCoeff() / std::max(1e-300, std::hypot(a_max, b_max) / std::sqrt(double(seeds)));
    const std::string name = model.nodes[key.first].name + (key.second ? "/back" : "/front");
    std::printf("%-14s %5d | %10.2e %10.2e   | %10.2e %10.2e   | %5.2f / %5.2f  (means differ by %.1f se)\n",
                name.c_str(), int(geo.size()), a_space, a_max, b_space, b_max, a_space / std::max(b_space, 1e-300),
                a_max / std::max(b_max, 1e-300), z);
    if (a_max > 1e-12 && b_max > 1e-12) {  // sides that see only space have no scatter
      log_gain += std::log(a_max / b_max);
      ++n_gain;
    }
  }
  std::printf("geometric mean gain (max sd, A / B): %.2f over %d node side-sets\n", std::exp(log_gain / std::max(1, n_gain)),
              n_gain);
  return 0;
}
