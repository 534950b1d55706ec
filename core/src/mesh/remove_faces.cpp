#include "thermodec/mesh/remove_faces.h"

#include <utility>

namespace thermodec {

std::vector<int> remove_faces(Mesh& mesh, const std::vector<char>& keep) {
  std::vector<int> kept;
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (keep[f]) kept.push_back(f);
  const int n = static_cast<int>(kept.size());
  auto attr = [](const Eigen::VectorXi& a, int f) { return a.size() > f ? a[f] : -1; };
  Mesh out;
  out.V = std::move(mesh.V);
  out.F.resize(n, 3);
  out.face_node.resize(n);
  out.face_material.resize(n);
  out.face_back_material.resize(n);
  for (int k = 0; k < n; ++k) {
    const int f = kept[k];
    out.F.row(k) = mesh.F.row(f);
    out.face_node[k] = attr(mesh.face_node, f);
    out.face_material[k] = attr(mesh.face_material, f);
    out.face_back_material[k] = attr(mesh.face_back_material, f);
  }
  out.node_names = std::move(mesh.node_names);
  out.material_names = std::move(mesh.material_names);
  mesh = std::move(out);
  return kept;
}

}  // namespace thermodec
