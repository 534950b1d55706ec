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

double mean_over(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& n,
                 const std::vector<Eigen::Vector3d>& p) {
  static const Dunavant5 rule;
  double sum = 0.0;
  for (int q = 0; q < 7; ++q) {
    const Eigen::Vector3d x = rule.bary[q][0] * a + rule.bary[q][1] * b + rule.bary[q][2] * c;
    sum += rule.weight[q] * point_to_polygon_view_factor(x, n, p);
  }
  return sum;
}

// Mean of the view factor over (a, b, c), whose coarse estimate is `coarse`; `share` is this
// triangle's fraction of the whole one's area.
double refine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& n,
              const std::vector<Eigen::Vector3d>& p, double coarse, double share, double tolerance, int depth) {
  const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const std::array<std::array<Eigen::Vector3d, 3>, 4> child = {
      {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}}};
  std::array<double, 4> m;
  for (int k = 0; k < 4; ++k) m[k] = mean_over(child[k][0], child[k][1], child[k][2], n, p);
  const double fine = 0.25 * (m[0] + m[1] + m[2] + m[3]);
  if (depth <= 0 || std::abs(fine - coarse) * share <= tolerance) return fine;
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    sum += refine(child[k][0], child[k][1], child[k][2], n, p, m[k], 0.25 * share, tolerance, depth - 1);
  return 0.25 * sum;
}

}  // namespace

double triangle_to_polygon_view_factor(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                       const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& p,
                                       double tolerance, int max_depth) {
  const std::vector<Eigen::Vector3d> front = clip_polygon_to_half_space(p, a, n);
  if (front.empty()) return 0.0;
  return refine(a, b, c, n, front, mean_over(a, b, c, n, front), 1.0, tolerance, max_depth);
}

}  // namespace thermodec
