#pragma once
// Small hand-built meshes and file helpers shared by the mesh tests.
#include <filesystem>
#include <fstream>
#include <string>

#include "common/scratch_dir.h"
#include "thermodec/mesh/mesh.h"

namespace thermodec::test {

inline std::filesystem::path temp_dir(const std::string& name) { return scratch_dir("thermodec_test_mesh", name); }

inline std::filesystem::path write_file(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
  return p;
}

//! Unit cube [0,1]^3, 8 vertices, 12 outward triangles; each side is its own node
//! ("px","nx","py","ny","pz","nz"); the +x side uses material "osr", the others "paint";
//! the +z side is two-sided with back material "mli".
inline Mesh unit_cube() {
  Mesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  m.F.resize(12, 3);
  m.F << 1, 3, 7, 1, 7, 5,  // +x
      0, 4, 6, 0, 6, 2,     // -x
      2, 6, 7, 2, 7, 3,     // +y
      0, 1, 5, 0, 5, 4,     // -y
      4, 5, 7, 4, 7, 6,     // +z
      0, 2, 3, 0, 3, 1;     // -z
  m.node_names = {"px", "nx", "py", "ny", "pz", "nz"};
  m.material_names = {"paint", "osr", "mli"};
  m.face_node.resize(12);
  m.face_material.resize(12);
  m.face_back_material = Eigen::VectorXi::Constant(12, -1);
  for (int f = 0; f < 12; ++f) {
    m.face_node[f] = f / 2;
    m.face_material[f] = f / 2 == 0 ? 1 : 0;
  }
  m.face_back_material[8] = m.face_back_material[9] = 2;
  return m;
}

}  // namespace thermodec::test
