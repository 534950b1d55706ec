// Earth view factors and albedo lighting from escaping hemisphere rays (Earth moving in body
// axes). Each side traces once a set of cosine-weighted (Malley) hemisphere rays, the ray
// stage's Owen-scrambled Sobol points; at each step the escaping directions inside the Earth's
// cone give F_side->Earth = hits / N (binomial error sqrt((1 - F) / (F N)), not added to the
// loads' error estimate) and the albedo lighting sum over them of max(0, n_E . sun).
#include "escaping_rays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "thermodec/environment/orbit.h"

namespace thermodec::load_rays {

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
void earth_view_from_escaping(const EscapingRays& esc, const Eigen::Vector3d& earth_dir_in, double distance_m, double radius_m,
                              const Eigen::Vector3d& sun, Eigen::VectorXd& view_factor, Eigen::VectorXd& lit_sum) {
  const int ns = static_cast<int>(esc.begin.size()) - 1;
  const Eigen::Vector3d e = earth_dir_in.normalized();
  const double sin_half = radius_m / distance_m, cos_half = std::sqrt(1.0 - sin_half * sin_half);
  const double R2 = radius_m * radius_m, r2 = distance_m * distance_m;
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
        const Eigen::Vector3d n = (t * d - distance_m * e) / radius_m;
        f += w;
        lit += w * std::max(0.0, n.dot(sun));
      }
      view_factor[s] = f;
      lit_sum[s] = lit;
    }
  });
}

}  // namespace thermodec::load_rays
