#include "thermodec/rays/surface_sides.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>
#include <unordered_map>

#include "thermodec/rays/sampling.h"
#include "thermodec/common/errors.h"
#include "thermodec/rays/ray_scene.h"

namespace thermodec {

SurfaceSides surface_sides(const Mesh& mesh) {
  const int nf = mesh.num_faces();
  SurfaceSides s;
  s.front_side = Eigen::VectorXi::Constant(nf, -1);
  s.back_side = Eigen::VectorXi::Constant(nf, -1);
  std::vector<int> face, back, node, mat;
  std::vector<double> area;
  std::unordered_map<std::uint64_t, int> occurrences;
  for (int f = 0; f < nf; ++f) {
    if (mesh.F(f, 0) < 0 || mesh.F(f, 0) >= mesh.num_vertices() || mesh.F(f, 1) < 0 ||
        mesh.F(f, 1) >= mesh.num_vertices() || mesh.F(f, 2) < 0 || mesh.F(f, 2) >= mesh.num_vertices())
      throw InvalidInput("face " + std::to_string(f) + " has a vertex index out of range");
    if (!is_traceable_face(mesh, f)) continue;
    const bool two_sided = mesh.is_two_sided(f);
    std::uint64_t h = 0x7468657264656331ull;  // "thermdec1"
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) h = sampling::hash_double(h, mesh.V(mesh.F(f, k), c));
    h = sampling::hash_combine(h, two_sided ? 2 : 1);
    h = sampling::hash_combine(h, std::uint64_t(occurrences[h]++));
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const double A = 0.5 * (b - a).cross(c - a).norm();
    for (int side = 0; side < (two_sided ? 2 : 1); ++side) {
      (side ? s.back_side : s.front_side)[f] = static_cast<int>(face.size());
      face.push_back(f);
      back.push_back(side);
      node.push_back(mesh.face_node.size() > f ? mesh.face_node[f] : -1);
      const Eigen::VectorXi& fm = side ? mesh.face_back_material : mesh.face_material;
      mat.push_back(fm.size() > f ? fm[f] : -1);
      area.push_back(A);
      s.key.push_back(sampling::hash_combine(h, std::uint64_t(side)));
    }
  }
  const int n = static_cast<int>(face.size());
  s.face = Eigen::Map<Eigen::VectorXi>(face.data(), n);
  s.is_back = Eigen::Map<Eigen::VectorXi>(back.data(), n);
  s.node = Eigen::Map<Eigen::VectorXi>(node.data(), n);
  s.material = Eigen::Map<Eigen::VectorXi>(mat.data(), n);
  s.area_m2 = Eigen::Map<Eigen::VectorXd>(area.data(), n);
  s.ir_boost = Eigen::VectorXd::Ones(n);
  s.load_boost = Eigen::VectorXd::Ones(n);
  return s;
}

SurfaceSides surface_sides(const ThermalModel& model) {
  SurfaceSides s = surface_sides(model.mesh);
  const int nn = static_cast<int>(model.nodes.size()), nm = static_cast<int>(model.materials.size());
  for (int i = 0; i < s.size(); ++i) {
    const int f = s.face[i];
    if (s.node[i] < -1 || s.node[i] >= nn)
      throw InvalidInput("face " + std::to_string(f) + " names node " + std::to_string(s.node[i]) + " but the model has " +
                         std::to_string(nn) + " nodes");
    int m = s.material[i];
    if (m < 0 && s.node[i] >= 0) m = model.nodes[s.node[i]].material;
    if (m < 0) m = model.default_material;
    if (m < 0 || m >= nm)
      throw InvalidInput("face " + std::to_string(f) + (s.is_back[i] ? " (back)" : "") + " has material " +
                         std::to_string(m) + " but the model has " + std::to_string(nm) + " materials");
    s.material[i] = m;
    if (s.node[i] >= 0 && model.nodes[s.node[i]].sampling_salt != 0)
      s.key[i] = sampling::hash_combine(s.key[i], model.nodes[s.node[i]].sampling_salt);
    if (s.node[i] >= 0) {
      const Node& nd = model.nodes[s.node[i]];
      for (double b : {nd.sampling_boost.ir, nd.sampling_boost.loads})
        if (!(b >= Node::SamplingBoost::kMin && b <= Node::SamplingBoost::kMax))
          throw InvalidInput("node '" + nd.name + "': sampling_boost " + std::to_string(b) +
                             " is outside [1/64, 10000]");
      s.ir_boost[i] = nd.sampling_boost.ir;
      s.load_boost[i] = nd.sampling_boost.loads;
    }
  }
  return s;
}

namespace {
Eigen::VectorXd side_property(const ThermalModel& model, const SurfaceSides& sides, bool emissivity) {
  Eigen::VectorXd out(sides.size());
  for (int i = 0; i < sides.size(); ++i) {
    const int m = sides.material[i];
    if (m < 0 || m >= static_cast<int>(model.materials.size()))
      throw InvalidInput("face " + std::to_string(sides.face[i]) + " has no material");
    const double v = emissivity ? model.materials[m].emissivity : model.materials[m].absorptivity;
    if (!(v > 0.0 && v <= 1.0))
      throw InvalidInput("material '" + model.materials[m].name + "': " + (emissivity ? "emissivity" : "absorptivity") +
                         " " + std::to_string(v) + " is outside (0, 1]");
    out[i] = v;
  }
  return out;
}
}  // namespace

Eigen::VectorXd side_emissivity(const ThermalModel& model, const SurfaceSides& sides) {
  return side_property(model, sides, true);
}
Eigen::VectorXd side_absorptivity(const ThermalModel& model, const SurfaceSides& sides) {
  return side_property(model, sides, false);
}

namespace {
int power_of_two_count(double r) {
  if (!(r > 1.0)) return 1;
  // 2^m <= r < 2^(m+1): up when r >= 2^m / ln 2, the split that neither adds nor removes
  // samples on average over counts spread evenly in log (E[2^m / r or 2^(m+1) / r] = 1).
  const double low = std::exp2(std::floor(std::log2(r)));
  const double out = r >= low / std::log(2.0) ? 2.0 * low : low;
  return static_cast<int>(std::min(out, double(1 << 30)));
}
}  // namespace

Eigen::VectorXi rays_per_side_of_node(const SurfaceSides& sides, int rays_per_side, int min_rays_per_node,
                                      const Eigen::VectorXd& boost) {
  const int ns = sides.size();
  int num_nodes = 0;
  for (int s = 0; s < ns; ++s) num_nodes = std::max(num_nodes, sides.node[s] + 1);
  // Faces, not sides: each side of a two-sided face is a surface of its own that the
  // minimum applies to (a two-sided node's fronts get it, and so do its backs).
  std::vector<double> area(num_nodes, 0.0);
  for (int s = 0; s < ns; ++s)
    if (sides.node[s] >= 0 && !sides.is_back[s]) area[sides.node[s]] += sides.area_m2[s];
  // The node's area rounded to a 1/64 octave (1.1 %): the decimator keeps node areas to
  // ~1e-5, so a node whose faces change elsewhere keeps the same rays on its unchanged faces
  // (correlated sampling, and no re-trace of the whole node when a neighbour's decimation
  // touches a few of its faces along their interface).
  for (double& a : area)
    if (a > 0.0) a = std::exp2(std::round(std::log2(a) * 64.0) / 64.0);
  Eigen::VectorXi rays(ns);
  for (int s = 0; s < ns; ++s) {
    const double b = boost.size() == ns ? boost[s] : 1.0;
    double r = std::ceil(rays_per_side * b);
    const int n = sides.node[s];
    if (n >= 0 && min_rays_per_node > 0 && area[n] > 0.0)
      r = std::max(r, std::ceil(double(min_rays_per_node) * b * sides.area_m2[s] / area[n]));
    rays[s] = power_of_two_count(std::min(r, 1e9));
  }
  return rays;
}

}  // namespace thermodec
