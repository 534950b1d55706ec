#include "thermodec/mesh/enclosing_shells.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <vector>

#include "thermodec/mesh/mesh_stats.h"

namespace thermodec {

std::vector<char> closed_components(const Eigen::MatrixXi& F, Eigen::VectorXi& component) {
  const int nf = static_cast<int>(F.rows());
  component = face_components(F);
  const int nc = nf ? component.maxCoeff() + 1 : 0;
  std::vector<std::tuple<int, int, int>> edges;  // (min vertex, max vertex, face)
  edges.reserve(3 * static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b), f);
    }
  std::sort(edges.begin(), edges.end());
  std::vector<char> closed(nc, 1);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
           std::get<1>(edges[j]) == std::get<1>(edges[i]))
      ++j;
    if (j - i == 1) closed[component[std::get<2>(edges[i])]] = 0;
    i = j;
  }
  return closed;
}

namespace {

// A closed part seen along one fixed direction: its triangles in a rotated frame whose x axis is
// the ray direction, bucketed on a uniform grid of the (y, z) plane. The direction is generic
// (no CAD axis or diagonal), so the projected edges of axis-aligned geometry do not pass
// through the test points.
class CrossingGrid {
 public:
  CrossingGrid(const std::vector<std::array<Eigen::Vector3d, 3>>& tris, double on_surface_m) : eps_(on_surface_m) {
    rot_ = (Eigen::AngleAxisd(0.5235987755982988 + 0.0123, Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(0.3490658503988659 + 0.0071, Eigen::Vector3d::UnitY()))
               .toRotationMatrix()
               .transpose();
    for (const auto& t : tris) {
      Tri r;
      for (int k = 0; k < 3; ++k) r.v[k] = rot_ * t[k];
      const Eigen::Vector3d n = (r.v[1] - r.v[0]).cross(r.v[2] - r.v[0]);
      if (!(n.norm() > 0.0)) continue;
      r.n = n.normalized();
      for (const auto& v : r.v) box_.extend(v);
      tris_.push_back(r);
    }
    const int T = static_cast<int>(tris_.size());
    cells_ = std::max(1, static_cast<int>(std::sqrt(double(T))));
    lo_ = box_.min().tail<2>();
    const Eigen::Vector2d ext = (box_.max().tail<2>() - lo_).cwiseMax(1e-300);
    inv_ = Eigen::Vector2d(cells_ / ext[0], cells_ / ext[1]);
    bucket_.assign(static_cast<size_t>(cells_) * cells_, {});
    for (int i = 0; i < T; ++i) {
      Eigen::AlignedBox2d b;
      for (const auto& v : tris_[i].v) b.extend(v.tail<2>());
      const auto [y0, z0] = cell(b.min());
      const auto [y1, z1] = cell(b.max());
      for (int y = y0; y <= y1; ++y)
        for (int z = z0; z <= z1; ++z) bucket_[static_cast<size_t>(y) * cells_ + z].push_back(i);
    }
  }

  //! Signed crossings of the ray from p along the direction (the winding number of a closed,
  //! outward surface: 1 inside, 0 outside), or NaN when p lies within eps of a triangle.
  double winding_number(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d p = rot_ * point;
    if (tris_.empty() || (p.tail<2>().array() < box_.min().tail<2>().array()).any() ||
        (p.tail<2>().array() > box_.max().tail<2>().array()).any() || p.x() > box_.max().x() + eps_)
      return 0.0;
    const auto [y, z] = cell(p.tail<2>());
    int w = 0;
    for (int i : bucket_[static_cast<size_t>(y) * cells_ + z]) {
      const Tri& t = tris_[i];
      // Edge functions of (p.y, p.z) in the projected triangle; its orientation is sign(n.x).
      auto edge = [&](int a, int b) {
        const Eigen::Vector2d u = t.v[a].tail<2>(), v = t.v[b].tail<2>(), q = p.tail<2>();
        return (v - u).x() * (q - u).y() - (v - u).y() * (q - u).x();
      };
      const double e0 = edge(0, 1), e1 = edge(1, 2), e2 = edge(2, 0);
      if (!((e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0))) continue;
      const double h = (p - t.v[0]).dot(t.n);  // signed distance of p from the plane [m]
      if (std::abs(h) <= eps_) return std::nan("");
      if (h * t.n.x() < 0) w += t.n.x() > 0 ? 1 : -1;  // the plane lies ahead of p along +x
    }
    return w;
  }

 private:
  struct Tri {
    std::array<Eigen::Vector3d, 3> v;
    Eigen::Vector3d n;
  };
  std::pair<int, int> cell(const Eigen::Vector2d& q) const {
    auto c = [&](int k) { return std::clamp(static_cast<int>((q[k] - lo_[k]) * inv_[k]), 0, cells_ - 1); };
    return {c(0), c(1)};
  }
  double eps_;
  Eigen::Matrix3d rot_;
  std::vector<Tri> tris_;
  Eigen::AlignedBox3d box_;
  Eigen::Vector2d lo_, inv_;
  int cells_ = 1;
  std::vector<std::vector<int>> bucket_;
};

}  // namespace

EnclosingShells enclosing_shells(const Mesh& mesh, const Eigen::VectorXi& component, const std::vector<char>& closed,
                                 double on_surface_m) {
  const int nf = mesh.num_faces(), nc = static_cast<int>(closed.size());
  EnclosingShells out;
  out.shell_face.assign(nf, 0);
  out.enclosed_face.assign(nf, 0);
  auto corner = [&](int f, int k) -> Eigen::Vector3d { return mesh.V.row(mesh.F(f, k)).transpose(); };
  std::vector<std::vector<int>> faces_of(nc);
  for (int f = 0; f < nf; ++f) faces_of[component[f]].push_back(f);
  static constexpr double kBary[4][3] = {{1. / 3, 1. / 3, 1. / 3}, {.6, .2, .2}, {.2, .6, .2}, {.2, .2, .6}};
  std::vector<std::array<Eigen::Vector3d, 4>> points(nf);
  for (int f = 0; f < nf; ++f)
    for (int s = 0; s < 4; ++s)
      points[f][s] = kBary[s][0] * corner(f, 0) + kBary[s][1] * corner(f, 1) + kBary[s][2] * corner(f, 2);
  for (int c = 0; c < nc; ++c) {
    if (!closed[c] || faces_of[c].size() < 4) continue;
    std::vector<std::array<Eigen::Vector3d, 3>> tris;
    Eigen::AlignedBox3d box;
    for (int f : faces_of[c]) {
      tris.push_back({corner(f, 0), corner(f, 1), corner(f, 2)});
      for (const auto& v : tris.back()) box.extend(v);
    }
    box.min().array() -= on_surface_m;
    box.max().array() += on_surface_m;
    const CrossingGrid grid(tris, on_surface_m);
    bool shell = false;
    for (int f = 0; f < nf; ++f) {
      if (component[f] == c || (shell && out.enclosed_face[f])) continue;
      for (const Eigen::Vector3d& p : points[f]) {
        if (!box.contains(p)) continue;
        const double w = grid.winding_number(p);
        if (std::abs(w) > 0.5) {  // NaN (on the surface) compares false
          out.enclosed_face[f] = 1;
          shell = true;
          break;
        }
      }
    }
    if (!shell) continue;
    ++out.shells;
    for (int f : faces_of[c]) out.shell_face[f] = 1;
  }
  return out;
}

}  // namespace thermodec
