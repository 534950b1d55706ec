// How much of each side's Earth cone could the spacecraft block at all? A measurement for a
// variance reduction thermodec does not apply (see docs/thermal.md): split the cone into K x K
// equal-solid-angle direction cells ((1 - cos a) and azimuth about the Earth's centre); a cell
// that no other face's bounding sphere can meet from the side's bounding sphere is open for
// every ray, so its Earth view and albedo need no tracing and add no binomial noise. If only a
// share f of a partly blocked side's cos-weighted cone is "maybe" cells, aiming all its rays
// there divides the variance of its blocked share by about 1 / f.
// Usage: bench_earth_cells [MODEL] [K=16]. Nadir attitude (Earth fixed in body axes), t = 0.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "thermodec/environment/orbit.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/rays/surface_sides.h"

using namespace thermodec;
using V3 = Eigen::Vector3d;

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json";
  const int K = argc > 2 ? std::stoi(argv[2]) : 16;
  const ThermalModel model = load_model(path);
  const SurfaceSides sides = surface_sides(model);
  const OrbitState st = orbit_state(model.environment, 0.0);
  const V3 e = st.earth_direction_body.normalized();
  const double sin_half = kEarthRadius_m / orbit_radius_m(model.environment.altitude_km);
  const double one_minus_cos_half = 1.0 - std::sqrt(1.0 - sin_half * sin_half);
  V3 t = e.unitOrthogonal(), u = e.cross(t);

  // Cell centre directions and angular radii (conservative: half the polar extent plus the
  // azimuthal arc at the cell's largest polar angle).
  std::vector<V3> centre(K * K);
  std::vector<double> radius(K * K);
  for (int i = 0; i < K; ++i) {
    const double a0 = std::acos(1.0 - one_minus_cos_half * i / K), a1 = std::acos(1.0 - one_minus_cos_half * (i + 1) / K);
    const double am = 0.5 * (a0 + a1);
    for (int j = 0; j < K; ++j) {
      const double ph = 2.0 * M_PI * (j + 0.5) / K;
      centre[i * K + j] = std::cos(am) * e + std::sin(am) * (std::cos(ph) * t + std::sin(ph) * u);
      radius[i * K + j] = 0.5 * (a1 - a0) + std::sin(a1) * M_PI / K + 1e-9;
    }
  }
  const int S = sides.size(), F = static_cast<int>(model.mesh.F.rows());
  auto corner = [&](int f, int k) -> V3 { return model.mesh.V.row(model.mesh.F(f, k)).transpose(); };
  std::vector<V3> fc(F);
  std::vector<double> fr(F);
  for (int f = 0; f < F; ++f) {
    fc[f] = (corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3.0;
    fr[f] = std::max({(corner(f, 0) - fc[f]).norm(), (corner(f, 1) - fc[f]).norm(), (corner(f, 2) - fc[f]).norm()});
  }
  const int N = static_cast<int>(model.nodes.size());
  std::vector<double> w_all(N, 0.0), w_maybe(N, 0.0);
  std::vector<int> mixed(N, 0), total(N, 0);
  for (int s = 0; s < S; ++s) {
    const int f = sides.face[s], node = sides.node[s];
    if (node < 0) continue;
    V3 n = (corner(f, 1) - corner(f, 0)).cross(corner(f, 2) - corner(f, 0)).normalized();
    if (sides.is_back[s]) n = -n;
    std::vector<double> w(K * K);
    double all = 0.0;
    for (int c = 0; c < K * K; ++c) all += (w[c] = std::max(0.0, n.dot(centre[c])));
    if (all <= 0.0) continue;
    ++total[node];
    std::vector<char> maybe(K * K, 0);
    for (int g = 0; g < F; ++g) {
      if (g == f) continue;
      // nowhere above the side's plane (behind it, or coplanar neighbours of the same panel):
      // cannot block a ray leaving its front
      bool above = false;
      for (int k = 0; k < 3; ++k) above |= n.dot(corner(g, k) - corner(f, 0)) > 1e-9 * (1.0 + fc[f].norm());
      if (!above) continue;
      const V3 v = fc[g] - fc[f];
      const double reach = fr[g] + fr[f], dist = v.norm();
      if (dist <= reach) {
        std::fill(maybe.begin(), maybe.end(), 1);
        break;
      }
      const double beta = std::asin(reach / dist);
      for (int c = 0; c < K * K; ++c)
        if (!maybe[c] && w[c] > 0.0 && std::acos(std::clamp(v.dot(centre[c]) / dist, -1.0, 1.0)) <= beta + radius[c]) maybe[c] = 1;
    }
    double wm = 0.0;
    for (int c = 0; c < K * K; ++c) wm += maybe[c] ? w[c] : 0.0;
    if (wm <= 0.0) continue;  // unobstructed: exact already
    ++mixed[node];
    const double a = sides.area_m2[s];
    w_all[node] += a * all;
    w_maybe[node] += a * wm;
  }
  std::printf("%s: %d x %d Earth-cone cells; per node: sides seeing the Earth, of which maybe blocked; share of "
              "their cos-weighted cone in cells some face may block (area-weighted)\n",
              path.c_str(), K, K);
  for (int k = 0; k < N; ++k)
    std::printf("  %-12s %5d %5d  %6.3f\n", model.nodes[k].name.c_str(), total[k], mixed[k],
                w_all[k] > 0.0 ? w_maybe[k] / w_all[k] : 0.0);
  return 0;
}
