#include "thermodec/radiation/planar_strata.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

#include "thermodec/mesh/face_geometry.h"
#include "thermodec/radiation/polygon_view_factor.h"
#include "thermodec/radiation/side_strata_of.h"
#include "thermodec/rays/tracing.h"

namespace thermodec {
namespace {

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Convex hull (Andrew's monotone chain), counter-clockwise, collinear points dropped.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return {};
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

double polygon_area(const std::vector<Eigen::Vector2d>& h) {
  double a = 0.0;
  for (std::size_t k = 0; k < h.size(); ++k) {
    const Eigen::Vector2d& p = h[k];
    const Eigen::Vector2d& q = h[(k + 1) % h.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * std::abs(a);
}

// The side of a hull's plane all points are on (+1 / -1), counting points within `tol` of
// the plane as on either side, at least one beyond it; 0 if they straddle or all lie in it.
// (A ray from a point in the plane never crosses it: such points do not matter.)
int closed_side(const NodeHull& h, const std::vector<Eigen::Vector3d>& pts, double tol) {
  int sign = 0;
  for (const Eigen::Vector3d& x : pts) {
    const double d = h.normal.dot(x) - h.offset;
    const int s = d > tol ? 1 : (d < -tol ? -1 : 0);
    if (s == 0) continue;
    if (sign != 0 && s != sign) return 0;
    sign = s;
  }
  return sign;
}

}  // namespace

namespace {

// A hull in the plane normal . y = offset from points of the node (projected onto it): its
// frame, convex hull and the single-precision copies of the per-ray test. False if the points
// span no area.
bool hull_in_plane(int node, const Eigen::Vector3d& normal, double offset, const std::vector<Eigen::Vector3d>& points,
                   NodeHull& h) {
  h.node = node;
  h.normal = normal;
  h.offset = offset;
  sampling::basis(h.normal, h.axis_u, h.axis_v);
  std::vector<Eigen::Vector2d> uv;
  for (const Eigen::Vector3d& x : points) uv.emplace_back(h.axis_u.dot(x), h.axis_v.dot(x));
  h.vertices_uv = convex_hull(std::move(uv));
  if (h.vertices_uv.size() < 3) return false;
  for (const Eigen::Vector2d& p : h.vertices_uv) h.vertices.push_back(h.offset * h.normal + p.x() * h.axis_u + p.y() * h.axis_v);
  for (int d = 0; d < 3; ++d) {
    h.fnormal[d] = float(h.normal[d]);
    h.fu[d] = float(h.axis_u[d]);
    h.fv[d] = float(h.axis_v[d]);
  }
  h.foffset = float(h.offset);
  for (std::size_t q = 0; q < h.vertices_uv.size(); ++q) {
    const Eigen::Vector2d& p0 = h.vertices_uv[q];
    const Eigen::Vector2d e = h.vertices_uv[(q + 1) % h.vertices_uv.size()] - p0;
    h.edges.push_back({float(-e.y()), float(e.x()), float(-e.y() * p0.x() + e.x() * p0.y())});
  }
  return true;
}

std::vector<Eigen::Vector3d> face_corners(const Mesh& mesh, const std::vector<int>& faces) {
  std::vector<Eigen::Vector3d> x;
  for (int f : faces)
    for (int c = 0; c < 3; ++c) x.emplace_back(mesh.V.row(mesh.F(f, c)));
  return x;
}

// The hull of one flat part (faces of one node in one plane), or none if its faces cover less
// than 90 % of it (an L-shaped plate: directions crossing the hull would mostly miss it).
bool flat_part_hull(const Mesh& mesh, const std::vector<int>& faces, int node, const Eigen::Vector3d& normal,
                    double offset, double area, NodeHull& h) {
  return hull_in_plane(node, normal, offset, face_corners(mesh, faces), h) && area >= 0.9 * polygon_area(h.vertices_uv);
}

// The aperture of a node shaped as a concave cap (a dish's front): its front faces' area-
// weighted mean normal d has at least half their area (|sum A n| >= 0.5 sum A) and points
// towards the node's centroid c on balance (sum A (c - c_f) . n_f > 0). The hull is the node's
// outline projected onto its supporting plane normal to d, set 2e-5 x the node's size beyond
// its farthest vertex (past the 1e-5 origin lift of its rays, sampling::make_emitter). A ray
// from the concave side crosses it iff it leaves the cap's convex hull through the opening.
bool aperture_hull(const Mesh& mesh, const std::vector<int>& faces, const Eigen::MatrixXd& N, const Eigen::VectorXd& A,
                   int node, NodeHull& h) {
  Eigen::Vector3d sum_an = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
  double area = 0.0;
  std::vector<Eigen::Vector3d> centroid;
  for (int f : faces) {
    centroid.emplace_back((mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2))).transpose() / 3.0);
    sum_an += A[f] * N.row(f).transpose();
    c += A[f] * centroid.back();
    area += A[f];
  }
  if (!(area > 0.0) || sum_an.norm() < 0.5 * area) return false;
  c /= area;
  double facing = 0.0;
  for (std::size_t k = 0; k < faces.size(); ++k) facing += A[faces[k]] * (c - centroid[k]).dot(N.row(faces[k]).transpose());
  if (!(facing > 0.0)) return false;
  const Eigen::Vector3d d = sum_an.normalized();
  const std::vector<Eigen::Vector3d> x = face_corners(mesh, faces);
  double top = -std::numeric_limits<double>::infinity(), size = 0.0;
  for (const Eigen::Vector3d& p : x) {
    top = std::max(top, d.dot(p));
    size = std::max(size, p.cwiseAbs().maxCoeff());
  }
  for (const Eigen::Vector3d& p : x) size = std::max(size, (p - x.front()).norm());
  h.aperture = true;
  return hull_in_plane(node, d, top + 2e-5 * size, x, h);
}

}  // namespace

std::vector<NodeHull> planar_node_hulls(const Mesh& mesh, const SurfaceSides& sides, int num_nodes, int max_hulls) {
  const Eigen::MatrixXd N = face_normals(mesh.V, mesh.F);
  const Eigen::VectorXd A = face_areas(mesh.V, mesh.F);
  const double extent = mesh.num_vertices() ? (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm() : 0.0;
  const double tol = 1e-9 * std::max(extent, 1e-30);
  // Per node, its faces grouped by plane (the first face of a group sets the plane).
  struct Part {
    int node;
    Eigen::Vector3d normal;
    double offset, area = 0.0;
    std::vector<int> faces;
  };
  std::vector<std::vector<Part>> parts(num_nodes);
  for (int s = 0; s < sides.size(); ++s) {
    const int j = sides.node[s], f = sides.face[s];
    if (sides.is_back[s] || j < 0 || j >= num_nodes || !(N.row(f).norm() > 0.5)) continue;
    const Eigen::Vector3d n = N.row(f).transpose();
    Part* into = nullptr;
    for (Part& p : parts[j]) {
      if (std::abs(std::abs(p.normal.dot(n)) - 1.0) >= 1e-9) continue;
      bool in = true;
      for (int c = 0; c < 3 && in; ++c) in = std::abs(p.normal.dot(Eigen::Vector3d(mesh.V.row(mesh.F(f, c)))) - p.offset) <= tol;
      if (in) {
        into = &p;
        break;
      }
    }
    if (!into) {
      parts[j].push_back(Part{j, n, n.dot(Eigen::Vector3d(mesh.V.row(mesh.F(f, 0)))), 0.0, {}});
      into = &parts[j].back();
    }
    into->faces.push_back(f);
    into->area += A[f];
  }
  // Flat nodes, the largest parts first (ties: node, then order found), at most max_hulls.
  std::vector<const Part*> order;
  // Only nodes that are one flat part: a box-shaped node's faces as controls measured worse on
  // the sample (docs/benchmarks.md).
  for (const auto& per_node : parts)
    if (per_node.size() == 1) order.push_back(&per_node.front());
  std::stable_sort(order.begin(), order.end(), [](const Part* x, const Part* y) { return x->area > y->area; });
  std::vector<NodeHull> out;
  for (const Part* p : order) {
    if (static_cast<int>(out.size()) == max_hulls) break;
    NodeHull h;
    if (flat_part_hull(mesh, p->faces, p->node, p->normal, p->offset, p->area, h)) out.push_back(std::move(h));
  }
  // Nodes of several planes: their aperture if they are concave caps (only their own sides
  // test it, so these do not count against max_hulls).
  for (int j = 0; j < num_nodes; ++j) {
    if (parts[j].size() < 2) continue;
    std::vector<int> faces;
    for (const Part& p : parts[j]) faces.insert(faces.end(), p.faces.begin(), p.faces.end());
    std::sort(faces.begin(), faces.end());
    NodeHull h;
    if (aperture_hull(mesh, faces, N, A, j, h)) out.push_back(std::move(h));
  }
  return out;
}

std::vector<SideStrata> side_strata(const Mesh& mesh, const SurfaceSides& sides, const std::vector<NodeHull>& hulls,
                                    double min_share) {
  const int S = sides.size();
  std::vector<SideStrata> out(S);
  if (hulls.empty()) return out;
  const double extent = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  const double tol = 1e-9 * std::max(extent, 1e-30);
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 16), [&](const tbb::blocked_range<int>& r) {
    std::vector<std::pair<double, int>> cand;
    for (int s = r.begin(); s != r.end(); ++s) {
      const sampling::Emitter e = tracing::side_emitter(mesh, sides, s, 0);
      const Eigen::Vector3d a = e.a + e.n * e.offset;  // the lifted triangle the rays start on
      const std::vector<Eigen::Vector3d> tri{a, a + e.e1, a + e.e2};
      cand.clear();
      for (int k = 0; k < static_cast<int>(hulls.size()); ++k) {
        // A flat node's hull serves the other nodes' sides, an aperture its own node's.
        if ((hulls[k].node == sides.node[s]) != hulls[k].aperture || closed_side(hulls[k], tri, tol) == 0) continue;
        const double u = triangle_to_polygon_view_factor(tri[0], tri[1], tri[2], e.n, hulls[k].vertices);
        if (u >= min_share && u <= 1.0 - min_share) cand.emplace_back(u, k);  // a near-constant indicator explains nothing
      }
      out[s] = side_strata_of(cand, hulls, [&](const std::vector<std::vector<Eigen::Vector3d>>& ps) {
        return triangle_to_polygons_view_factor(tri[0], tri[1], tri[2], e.n, ps);
      });
    }
  });
  return out;
}

int stratum_of_ray(const SideStrata& strata, const std::vector<NodeHull>& hulls, const float* org, const float* dir) {
  int mask = 0;
  for (int k = 0; k < strata.count; ++k) {
    const NodeHull& h = hulls[strata.hull[k]];
    const float den = h.fnormal[0] * dir[0] + h.fnormal[1] * dir[1] + h.fnormal[2] * dir[2];
    const float num = h.foffset - (h.fnormal[0] * org[0] + h.fnormal[1] * org[1] + h.fnormal[2] * org[2]);
    if (!(num * den > 0.0f)) continue;  // the plane is behind the ray, or parallel to it
    const float t = num / den;
    float x[3];
    for (int d = 0; d < 3; ++d) x[d] = org[d] + t * dir[d];
    const float u = h.fu[0] * x[0] + h.fu[1] * x[1] + h.fu[2] * x[2];
    const float v = h.fv[0] * x[0] + h.fv[1] * x[1] + h.fv[2] * x[2];
    bool inside = true;
    for (const auto& e : h.edges)
      if (e[0] * u + e[1] * v < e[2]) {
        inside = false;
        break;
      }
    if (inside) mask |= 1 << k;
  }
  return mask;
}

namespace {
// The controls are the products c_T = prod_{k in T} c_k over every non-empty set T of the
// side's hulls (index T - 1): c_T = 1 for a ray iff T lies within the mask of hulls it crossed.
int num_controls(const SideStrata& strata) { return (1 << strata.count) - 1; }
bool within(int set, int mask) { return (set & mask) == set; }

// The means m of the controls over the side's rays (from the rays per mask) and the
// pseudo-inverse of their covariance: a set no ray crossed (or every ray did), or two crossed
// by the same rays, add nothing.
void indicator_moments(const SideStrata& strata, const std::vector<double>& rays_per_stratum, Eigen::VectorXd& m,
                       Eigen::MatrixXd& pinv) {
  const int k = num_controls(strata), M = 1 << strata.count;
  double R = 0.0;
  for (double n : rays_per_stratum) R += n;
  m = Eigen::VectorXd::Zero(k);
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(k, k);
  for (int mask = 1; mask < M && R > 0.0; ++mask) {
    const double f = rays_per_stratum[mask] / R;
    if (f == 0.0) continue;
    for (int p = 1; p < M; ++p) {
      if (!within(p, mask)) continue;
      m[p - 1] += f;
      for (int q = 1; q < M; ++q)
        if (within(q, mask)) cov(p - 1, q - 1) += f;
    }
  }
  cov -= m * m.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  const double cut = 1e-10 * std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  Eigen::VectorXd inv(k);
  for (int p = 0; p < k; ++p) inv[p] = eig.eigenvalues()[p] > cut ? 1.0 / eig.eigenvalues()[p] : 0.0;
  pinv = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}
}  // namespace

std::vector<double> stratum_weights(const SideStrata& strata, const std::vector<double>& rays_per_stratum) {
  const int k = num_controls(strata), M = 1 << strata.count;
  double R = 0.0;
  for (double n : rays_per_stratum) R += n;
  std::vector<double> w(M, R > 0.0 ? 1.0 / R : 0.0);
  if (k == 0 || !(R > 0.0)) return w;
  Eigen::VectorXd m, gap(k);
  Eigen::MatrixXd pinv;
  indicator_moments(strata, rays_per_stratum, m, pinv);
  for (int p = 1; p < M; ++p) gap[p - 1] = m[p - 1] - strata.joint[p];
  const Eigen::VectorXd b = pinv * gap;  // b = cov(c)^+ (m - U)
  const double base = 1.0 + b.dot(m);
  for (int mask = 0; mask < M; ++mask) {
    double x = base;
    for (int p = 1; p < M; ++p)
      if (within(p, mask)) x -= b[p - 1];
    w[mask] = x / R;
  }
  return w;
}

Eigen::RowVectorXd controlled_score_variance(const ControlledSide& side,
                                            const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& score,
                                            const Eigen::RowVectorXd& space_score) {
  const int k = num_controls(side.strata), M = 1 << side.strata.count, C = static_cast<int>(score.cols());
  Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(C), second = Eigen::RowVectorXd::Zero(C);
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(k, C);  // E[c_p score]
  Eigen::RowVectorXd e(C);
  for (int mask = 0; mask < M; ++mask) {
    e.setZero();
    for (const auto& [t, f] : side.hits[mask]) {
      const auto y = t < 0 ? space_score : Eigen::RowVectorXd(score.row(t));
      e.noalias() += f * y;
      second.noalias() += f * y.cwiseAbs2();
    }
    mean += e;
    for (int p = 1; p < M; ++p)
      if (within(p, mask)) cross.row(p - 1) += e;
  }
  Eigen::VectorXd m;
  Eigen::MatrixXd pinv;
  indicator_moments(side.strata, side.rays_per_stratum, m, pinv);
  const Eigen::MatrixXd g = cross - m * mean;  // cov(c, score), k x C
  const Eigen::RowVectorXd explained = (g.array() * (pinv * g).array()).colwise().sum();
  return (second - mean.cwiseAbs2() - explained).cwiseMax(0.0);
}

}  // namespace thermodec
