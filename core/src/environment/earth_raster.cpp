// The Earth view of a face side by rasterising its blockers over a grid of the Earth's cone.
//
// Per side: the faces that may meet its Earth cone (the conservative bounding-sphere test of
// may_be_blocked_from_earth) are projected, from each sample origin on the side, onto the
// gnomonic plane about the Earth direction (a triangle stays a triangle there, clipped to the
// half-space in front of the origin) and rasterised as row spans into a 64 x 64 coverage mask.
// The blocked share seen from an origin is the cos-weighted solid angle of its covered pixels;
// F_side->Earth = F_open x (1 - mean over origins of that share), F_open the closed form of
// the unobstructed view. The origins are the ray stage's Owen-scrambled Sobol points, so the
// only seed-dependent part is a 2-D average of a function continuous in the origin; the grid
// is fixed (its discretisation, measured against brute-force rays in the tests, does not
// change with the seed).
#include "earth_raster.h"

#include <algorithm>
#include <limits>
#include <cmath>

namespace thermodec::load_rays {

EarthGrid::EarthGrid(const Eigen::Vector3d& earth_dir, const Eigen::Vector3d& t_in, const Eigen::Vector3d& u_in,
                     double distance_m, double radius_m)
    : e(earth_dir), t(t_in), u(u_in) {
  const double sin_half = radius_m / distance_m, cos_half = std::sqrt(1.0 - sin_half * sin_half);
  tan_half = sin_half / cos_half;
  step = 2.0 * tan_half / kN;
  const int P = kN * kN;
  dir.assign(P, Eigen::Vector3d::Zero());
  solid_angle_over_pi.assign(P, 0.0);
  earth_normal.assign(P, Eigen::Vector3f::Zero());
  const double R2 = radius_m * radius_m, D = distance_m;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const double X = -tan_half + (i + 0.5) * step, Y = -tan_half + (j + 0.5) * step, r2 = X * X + Y * Y;
      if (r2 > tan_half * tan_half) continue;
      const int p = j * kN + i;
      const double q = 1.0 + r2, inv = 1.0 / std::sqrt(q);
      dir[p] = (e + X * t + Y * u) * inv;
      solid_angle_over_pi[p] = step * step * inv * inv * inv / 3.14159265358979323846;
      // The Earth's normal where the direction meets it (seen from the body origin, as the cone rays).
      const double cos_a = inv, sin2_a = r2 / q;
      const double t_hit = D * cos_a - std::sqrt(std::max(0.0, R2 - D * D * sin2_a));
      earth_normal[p] = ((t_hit * dir[p] - D * e) / radius_m).cast<float>();
      in_cone[j] |= std::uint64_t{1} << i;
    }
}

namespace {

// Sets in `cover` the pixels whose centre lies in triangle (a, b, c) [m] seen from `o` [m].
void rasterise(const EarthGrid& grid, const Eigen::Vector3d& o, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               const Eigen::Vector3d& c, std::array<std::uint64_t, EarthGrid::kN>& cover) {
  constexpr int kN = EarthGrid::kN;
  double x[3], y[3], z[3], reach = 0.0;
  const Eigen::Vector3d* v[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = *v[k] - o;
    x[k] = d.dot(grid.t);
    y[k] = d.dot(grid.u);
    z[k] = d.dot(grid.e);
    reach = std::max(reach, d.cwiseAbs().maxCoeff());
  }
  // Clip to the half-space z >= z_min in front of the origin (what lies behind cannot block
  // a direction of the cone); project onto the plane z = 1.
  const double z_min = 1e-7 * reach + 1e-12;
  double px[4], py[4];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    const bool in_k = z[k] >= z_min, in_l = z[l] >= z_min;
    if (in_k) {
      px[n] = x[k] / z[k];
      py[n++] = y[k] / z[k];
    }
    if (in_k != in_l) {
      const double s = (z_min - z[k]) / (z[l] - z[k]);
      px[n] = (x[k] + s * (x[l] - x[k])) / z_min;
      py[n++] = (y[k] + s * (y[l] - y[k])) / z_min;
    }
  }
  if (n < 3) return;
  const double T = grid.tan_half, inv_step = 1.0 / grid.step;
  double y_lo = py[0], y_hi = py[0];
  for (int k = 1; k < n; ++k) {
    y_lo = std::min(y_lo, py[k]);
    y_hi = std::max(y_hi, py[k]);
  }
  // Rows whose centre Y_j = -T + (j + 0.5) step lies in [y_lo, y_hi].
  const double j_lo = std::ceil(std::clamp((y_lo + T) * inv_step - 0.5, -1.0, double(kN))),
               j_hi = std::floor(std::clamp((y_hi + T) * inv_step - 0.5, -1.0, double(kN)));
  for (int j = std::max(0, int(j_lo)); j <= std::min(kN - 1, int(j_hi)); ++j) {
    const double yc = -T + (j + 0.5) * grid.step;
    double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
    for (int k = 0; k < n; ++k) {
      const int l = k + 1 < n ? k + 1 : 0;
      const double ya = py[k], yb = py[l];
      if ((ya < yc && yb < yc) || (ya > yc && yb > yc)) continue;
      if (ya == yb) {
        x_lo = std::min({x_lo, px[k], px[l]});
        x_hi = std::max({x_hi, px[k], px[l]});
      } else {
        const double xc = px[k] + (yc - ya) * (px[l] - px[k]) / (yb - ya);
        x_lo = std::min(x_lo, xc);
        x_hi = std::max(x_hi, xc);
      }
    }
    if (!(x_lo <= x_hi)) continue;
    const double i_lo = std::ceil(std::clamp((x_lo + T) * inv_step - 0.5, -1.0, double(kN))),
                 i_hi = std::floor(std::clamp((x_hi + T) * inv_step - 0.5, -1.0, double(kN)));
    const int i0 = std::max(0, int(i_lo)), i1 = std::min(kN - 1, int(i_hi));
    if (i0 > i1) continue;
    cover[j] |= (~std::uint64_t{0} >> (63 - (i1 - i0))) << i0;
  }
}

}  // namespace

RasterView earth_view_by_raster(const EarthGrid& grid, const std::vector<Side>& geo, const Occluders& occ, int s,
                                bool may_be_blocked, double sin_half, double f_open, int origins, int rays,
                                const std::array<std::uint32_t, 4>& sd, const tracing::SobolTable& sobol,
                                RasterScratch& x, std::vector<std::pair<float, Eigen::Vector3f>>& keep) {
  constexpr int kN = EarthGrid::kN;
  const Side& g = geo[s];
  RasterView out;
  // Pixel weights dOmega / pi max(0, n . w): the directions in front of the side.
  x.weight.assign(kN * kN, 0.0);
  double sum_w = 0.0;
  for (int j = 0; j < kN; ++j) {
    x.open[j] = 0;
    for (std::uint64_t m = grid.in_cone[j]; m; m &= m - 1) {
      const int i = __builtin_ctzll(m), p = j * kN + i;
      const double c = g.normal.dot(grid.dir[p]);
      if (c <= 0.0) continue;
      x.weight[p] = grid.solid_angle_over_pi[p] * c;
      sum_w += x.weight[p];
      x.open[j] |= std::uint64_t{1} << i;
    }
  }
  if (!(sum_w > 0.0) || !(f_open > 0.0)) return out;
  // The faces that may block: as may_be_blocked_from_earth, listed.
  x.blockers.clear();
  if (may_be_blocked && origins > 0) {
    const double cos_half = std::sqrt(1.0 - sin_half * sin_half), h = 0.5 * g.offset;
    const double slack = 1e-9 * (g.a.cwiseAbs().maxCoeff() + 1.0);
    auto meets = [&](const Eigen::Vector3d& centre, double reach) {
      return may_meet_earth_cone(occ.centre[s], g.normal, grid.e, sin_half, cos_half, centre, reach);
    };
    blockers::any_member(
        occ.tree,
        [&](const blockers::SphereTree::Node& n) {
          return blockers::height_above_plane(n, g.normal, g.a) > h - slack && meets(n.centre, occ.radius[s] + n.radius);
        },
        [&](int t) {
          if (occ.face[t] != occ.face[s] && !below_plane_of(g, geo[t]) && meets(occ.centre[t], occ.radius[s] + occ.radius[t]))
            x.blockers.push_back(t);
          return false;
        });
  }
  // Many blockers (large CAD meshes): rays, where rasterising would cost more than the side's
  // rays (a ray ~ kRasterTrianglesPerRay triangles). Fewer origins instead would raise the
  // side's estimated error and with it the noise-targeted boosts (measured on NPP_16).
  if (static_cast<double>(x.blockers.size()) * origins > kRasterTrianglesPerRay * rays) {
    out.by_rays = true;
    return out;
  }
  x.blocked_count.assign(kN * kN, 0);
  const double scale = f_open / sum_w;
  if (!x.blockers.empty()) {
    out.origins = origins;
    double sum_b = 0.0, sum_b2 = 0.0;
    for (int k = 0; k < origins; ++k) {
      float of[3];
      on_side(g, scrambled(sobol[k][0], sd[0]), scrambled(sobol[k][1], sd[1]), of);
      const Eigen::Vector3d o(of[0], of[1], of[2]);
      x.cover.fill(0);
      for (int t : x.blockers) rasterise(grid, o, geo[t].a, geo[t].b, geo[t].c, x.cover);
      double b = 0.0;
      for (int j = 0; j < kN; ++j)
        for (std::uint64_t m = x.cover[j] & x.open[j]; m; m &= m - 1) {
          const int p = j * kN + __builtin_ctzll(m);
          ++x.blocked_count[p];
          b += x.weight[p];
        }
      b /= sum_w;
      sum_b += b;
      sum_b2 += b * b;
    }
    // Error of the origins' average: their spread times N^-3/4 (a scrambled net on a function
    // that is continuous but kinked in the origin; the plain N^-1/2 overstates it).
    const double mean_b = sum_b / origins, p = 1.0 - mean_b;
    const double var = origins > 1 ? std::max(0.0, (sum_b2 - origins * mean_b * mean_b) / (origins - 1)) : 0.0;
    if (p > 0.0 && p < 1.0 - 1e-12) out.relative_error = std::sqrt(var) * std::pow(double(origins), -0.75) / p;
  }
  const double inv_origins = out.origins > 0 ? 1.0 / out.origins : 0.0;
  double f = 0.0;
  for (int j = 0; j < kN; ++j)
    for (std::uint64_t m = x.open[j]; m; m &= m - 1) {
      const int p = j * kN + __builtin_ctzll(m);
      const double visible = 1.0 - x.blocked_count[p] * inv_origins;
      if (visible <= 0.0) continue;
      const double w = scale * x.weight[p] * visible;
      keep.emplace_back(float(w), grid.earth_normal[p]);
      f += w;
    }
  out.view_factor = f;
  return out;
}

}  // namespace thermodec::load_rays
