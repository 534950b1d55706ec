#include "thermodec/radiation/polygon_view_factor.h"

#include <array>
#include <cmath>

namespace thermodec {

double point_to_polygon_view_factor(const Eigen::Vector3d& x, const Eigen::Vector3d& n,
                                    const std::vector<Eigen::Vector3d>& p) {
  const std::size_t m = p.size();
  if (m < 3) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d r0 = p[k] - x, r1 = p[(k + 1) % m] - x;
    const Eigen::Vector3d c = r0.cross(r1);
    const double s = c.norm();
    if (!(s > 0.0)) continue;  // an edge seen end-on subtends no angle
    sum += std::atan2(s, r0.dot(r1)) * n.dot(c) / s;
  }
  return std::abs(sum) / (2.0 * M_PI);
}

std::vector<Eigen::Vector3d> clip_polygon_to_half_space(const std::vector<Eigen::Vector3d>& p,
                                                        const Eigen::Vector3d& a, const Eigen::Vector3d& n) {
  std::vector<Eigen::Vector3d> out;
  const std::size_t m = p.size();
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d& u = p[k];
    const Eigen::Vector3d& v = p[(k + 1) % m];
    const double du = n.dot(u - a), dv = n.dot(v - a);
    if (du >= 0.0) out.push_back(u);
    if ((du >= 0.0) != (dv >= 0.0)) out.push_back(u + (du / (du - dv)) * (v - u));
  }
  if (out.size() < 3) out.clear();
  return out;
}

namespace {

// Dunavant's degree-5 rule on a triangle: 7 points (barycentric) and weights summing to 1.
struct Dunavant5 {
  std::array<std::array<double, 3>, 7> bary;
  std::array<double, 7> weight;
  Dunavant5() {
    const double a1 = 0.059715871789770, b1 = 0.470142064105115;
    const double a2 = 0.797426985353087, b2 = 0.101286507323456;
    bary = {{{1.0 / 3, 1.0 / 3, 1.0 / 3}, {a1, b1, b1}, {b1, a1, b1}, {b1, b1, a1}, {a2, b2, b2}, {b2, a2, b2}, {b2, b2, a2}}};
    weight = {0.225, 0.132394152788506, 0.132394152788506, 0.132394152788506,
              0.125939180544827, 0.125939180544827, 0.125939180544827};
  }
};

// Area mean over (a, b, c) of f(x) [-], f the view factor seen from the point x.
template <class PointFactor>
double mean_over(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const PointFactor& f) {
  static const Dunavant5 rule;
  double sum = 0.0;
  for (int q = 0; q < 7; ++q) {
    const Eigen::Vector3d x = rule.bary[q][0] * a + rule.bary[q][1] * b + rule.bary[q][2] * c;
    sum += rule.weight[q] * f(x);
  }
  return sum;
}

// Mean of f over (a, b, c), whose coarse estimate is `coarse`; `share` is this triangle's
// fraction of the whole one's area.
template <class PointFactor>
double refine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const PointFactor& f,
              double coarse, double share, double tolerance, int depth) {
  const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const std::array<std::array<Eigen::Vector3d, 3>, 4> child = {
      {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}}};
  std::array<double, 4> m;
  for (int k = 0; k < 4; ++k) m[k] = mean_over(child[k][0], child[k][1], child[k][2], f);
  const double fine = 0.25 * (m[0] + m[1] + m[2] + m[3]);
  if (depth <= 0 || std::abs(fine - coarse) * share <= tolerance) return fine;
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    sum += refine(child[k][0], child[k][1], child[k][2], f, m[k], 0.25 * share, tolerance, depth - 1);
  return 0.25 * sum;
}

template <class PointFactor>
double triangle_mean(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const PointFactor& f,
                     double tolerance, int max_depth) {
  return refine(a, b, c, f, mean_over(a, b, c, f), 1.0, tolerance, max_depth);
}

}  // namespace

double triangle_to_polygon_view_factor(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                       const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& p,
                                       double tolerance, int max_depth) {
  const std::vector<Eigen::Vector3d> front = clip_polygon_to_half_space(p, a, n);
  if (front.empty()) return 0.0;
  return triangle_mean(a, b, c, [&](const Eigen::Vector3d& x) { return point_to_polygon_view_factor(x, n, front); },
                       tolerance, max_depth);
}

std::vector<Eigen::Vector3d> clip_polygon_to_cone(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& x,
                                                  const std::vector<Eigen::Vector3d>& q) {
  const std::size_t m = q.size();
  if (m < 3 || p.empty()) return {};
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : q) g += v;
  g /= static_cast<double>(m);
  // x in q's plane (q seen edge-on): no direction crosses it.
  const Eigen::Vector3d nq = (q[1] - q[0]).cross(q[2] - q[0]);
  if (!(std::abs(nq.dot(x - q[0])) > 1e-12 * nq.norm() * (q[0] - x).norm())) return {};
  std::vector<Eigen::Vector3d> out = p;
  for (std::size_t k = 0; k < m && !out.empty(); ++k) {
    Eigen::Vector3d c = (q[k] - x).cross(q[(k + 1) % m] - x);
    if (c.dot(g - x) < 0.0) c = -c;  // towards the inside of the cone
    out = clip_polygon_to_half_space(out, x, c);
  }
  return out;
}

double triangle_to_polygons_view_factor(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                        const Eigen::Vector3d& n, const std::vector<std::vector<Eigen::Vector3d>>& ps,
                                        double tolerance, int max_depth) {
  if (ps.empty()) return 0.0;
  const std::vector<Eigen::Vector3d> front = clip_polygon_to_half_space(ps[0], a, n);
  if (front.empty()) return 0.0;
  const auto joint = [&](const Eigen::Vector3d& x) {
    std::vector<Eigen::Vector3d> p = front;
    for (std::size_t k = 1; k < ps.size() && !p.empty(); ++k) p = clip_polygon_to_cone(p, x, ps[k]);
    return p.empty() ? 0.0 : point_to_polygon_view_factor(x, n, p);
  };
  return triangle_mean(a, b, c, joint, tolerance, max_depth);
}

}  // namespace thermodec
