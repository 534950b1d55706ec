// NASTRAN bulk data writer. Field layouts: MSC Nastran Quick Reference Guide (GRID, CTRIA3,
// PSHELL, RADM). Coordinates go in large-field GRID* cards: small-field reals keep only ~6
// significant digits, which would move vertices of a metre-sized spacecraft by micrometres
// and change face areas in the last printed digits.
#include "thermodec/exchange/write_nastran_bulk.h"

#include <cstdio>
#include <map>
#include <ostream>

#include "number_text.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"

namespace thermodec {
namespace {

std::string small(const std::string& s) {  // one left-aligned 8-column field
  char buf[16];
  std::snprintf(buf, sizeof buf, "%-8s", s.c_str());
  return buf;
}

std::string large(const std::string& s) {  // one left-aligned 16-column field
  char buf[24];
  std::snprintf(buf, sizeof buf, "%-16s", s.c_str());
  return buf;
}

// A comment line must stay one line and comma-free (see the header comment below).
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == ',') c = ' ';
  return s;
}

}  // namespace

void write_nastran_bulk(const std::filesystem::path& path, const ThermalModel& model,
                        const std::vector<std::filesystem::path>& protected_inputs) {
  const Mesh& mesh = model.mesh;
  const int nf = mesh.num_faces();
  // One property id per (node, front material): usually one per node.
  std::map<std::pair<int, int>, int> pid_of;
  for (int f = 0; f < nf; ++f) {
    if (mesh.face_node[f] < 0 || mesh.face_material[f] < 0)
      throw InvalidInput("export nastran: face " + std::to_string(f) + " has no node or material");
    pid_of.emplace(std::make_pair(mesh.face_node[f], mesh.face_material[f]), 0);
  }
  int next = 1;
  for (auto& [key, pid] : pid_of) pid = next++;
  using exchange_text::nastran_real;
  write_file_atomically(path, [&](std::ostream& out) {
    // No card names and no commas in comments: some readers (FreeCAD's) search whole lines
    // for card names and switch to free field on any comma.
    out << "$ thermodec export: NASTRAN bulk data of the radiating surface mesh\n"
           "$ units: SI (m); radiation material = solar absorptivity and IR emissivity (front side)\n"
           "$ dialect: grid points large-field (16 columns); the other cards small-field (8 columns)\n"
           "$ ids: grid = vertex + 1; element = face + 1; property = thermal node (and material);\n"
           "$       material id = thermodec material + 1; names in the thermodec node and material comments\n"
           "$ source: " << one_line(model.mesh_path.string()) << "\n";
    if (model.certificate)
      for (const std::string& line : certificate_lines(*model.certificate)) out << "$ " << one_line(line) << "\n";
    out << "BEGIN BULK\n";
    for (std::size_t m = 0; m < model.materials.size(); ++m) {
      const Material& mat = model.materials[m];
      out << "$ thermodec material " << m + 1 << " " << one_line(mat.name) << "\n"
          << small("RADM") << small(std::to_string(m + 1)) << small(nastran_real(mat.absorptivity, 8))
          << small(nastran_real(mat.emissivity, 8)) << "\n";
    }
    for (const auto& [key, pid] : pid_of) {
      const int node = key.first;
      out << "$ thermodec node " << pid << " " << one_line(model.nodes[node].name) << "\n";
      // T (shell thickness) is nominal: thermodec models hold lumped capacitances, not thicknesses.
      out << small("PSHELL") << small(std::to_string(pid)) << small(std::to_string(key.second + 1)) << small("0.001") << "\n";
    }
    for (int f = 0; f < nf; ++f)
      if (mesh.is_two_sided(f)) {
        out << "$ two-sided faces (thin sheets) radiate from both sides; their back materials:\n";
        for (int g = f; g < nf; ++g)
          if (mesh.is_two_sided(g))
            out << "$ thermodec back_material " << g + 1 << " " << one_line(model.materials[mesh.face_back_material[g]].name) << "\n";
        break;
      }
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      out << small("GRID*") << large(std::to_string(v + 1)) << large("0") << large(nastran_real(mesh.V(v, 0), 16))
          << large(nastran_real(mesh.V(v, 1), 16)) << "\n"
          << small("*") << large(nastran_real(mesh.V(v, 2), 16)) << "\n";
    }
    for (int f = 0; f < nf; ++f)
      out << small("CTRIA3") << small(std::to_string(f + 1))
          << small(std::to_string(pid_of.at({mesh.face_node[f], mesh.face_material[f]}))) << small(std::to_string(mesh.F(f, 0) + 1))
          << small(std::to_string(mesh.F(f, 1) + 1)) << small(std::to_string(mesh.F(f, 2) + 1)) << "\n";
    out << "ENDDATA\n";
  }, protected_inputs);
}

}  // namespace thermodec
