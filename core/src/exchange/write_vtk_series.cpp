// VTK XML UnstructuredGrid (.vtu, ASCII, version 0.1) and ParaView data collection (.pvd):
// the layouts of the VTK file-format guide. ASCII keeps the files readable by any XML-aware
// tool (meshio, ParaView, VisIt) without a base64/zlib decoder.
#include "thermodec/exchange/write_vtk_series.h"

#include <cstdio>
#include <ostream>

#include "number_text.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/face_geometry.h"

namespace thermodec {
namespace {

using exchange_text::real;

std::string xml_escaped(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '&') o += "&amp;";
    else if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '"') o += "&quot;";
    else o += c;
  }
  return o;
}

template <class Value>
void data_array(std::ostream& out, const char* type, const std::string& name, int components, int count, Value value) {
  out << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\"" << components
      << "\" format=\"ascii\">\n";
  for (int i = 0; i < count; ++i) out << "          " << value(i) << "\n";
  out << "        </DataArray>\n";
}

// The cell data carry node and material ids; their names sit in XML comments at the top
// (string arrays are not read alike by VTK versions and meshio).
void write_vtu(std::ostream& out, const ThermalModel& model, const ExportedNetwork& e, const Eigen::VectorXd& area,
               const Eigen::VectorXd& node_flux, int step) {
  const Mesh& m = model.mesh;
  const int nv = m.num_vertices(), nf = m.num_faces();
  out << "<?xml version=\"1.0\"?>\n<!-- thermodec export: surface mesh [m] and per-face results at t = " << real(e.times_s[step])
      << " s; node_id/material_id index the names below (0-based) -->\n";
  for (const std::string& line : e.provenance) out << "<!-- " << xml_escaped(line) << " -->\n";
  for (int i = 0; i < e.num_nodes(); ++i) out << "<!-- node " << i << ": " << xml_escaped(e.network.node_names[i]) << " -->\n";
  for (std::size_t i = 0; i < model.materials.size(); ++i) out << "<!-- material " << i << ": " << xml_escaped(model.materials[i].name) << " -->\n";
  out << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << nv << "\" NumberOfCells=\"" << nf << "\">\n      <Points>\n";
  data_array(out, "Float64", "Points", 3, nv, [&](int v) { return real(m.V(v, 0)) + " " + real(m.V(v, 1)) + " " + real(m.V(v, 2)); });
  out << "      </Points>\n      <Cells>\n";
  data_array(out, "Int64", "connectivity", 1, nf, [&](int f) {
    return std::to_string(m.F(f, 0)) + " " + std::to_string(m.F(f, 1)) + " " + std::to_string(m.F(f, 2));
  });
  data_array(out, "Int64", "offsets", 1, nf, [&](int f) { return std::to_string(3 * (f + 1)); });
  data_array(out, "UInt8", "types", 1, nf, [&](int) { return std::string("5"); });  // VTK_TRIANGLE
  out << "      </Cells>\n      <CellData Scalars=\"temperature_K\">\n";
  data_array(out, "Int32", "node_id", 1, nf, [&](int f) { return std::to_string(m.face_node[f]); });
  data_array(out, "Int32", "material_id", 1, nf, [&](int f) { return std::to_string(m.face_material[f]); });
  data_array(out, "Float64", "area_m2", 1, nf, [&](int f) { return real(area[f]); });
  data_array(out, "Float64", "temperature_K", 1, nf, [&](int f) { return real(e.temperature_K(m.face_node[f], step)); });
  data_array(out, "Float64", "absorbed_flux_W_per_m2", 1, nf, [&](int f) { return real(node_flux[m.face_node[f]]); });
  out << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

// Removes DIR/STEM_NNNN.vtu for NNNN >= steps: what a longer earlier series left.
void remove_stale_steps(const std::filesystem::path& dir, const std::string& stem, int steps) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= stem.size() + 5 || name.compare(0, stem.size() + 1, stem + "_") != 0 ||
        entry.path().extension() != ".vtu")
      continue;
    const std::string digits = name.substr(stem.size() + 1, name.size() - stem.size() - 5);
    if (digits.size() < 4 || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    if (std::stol(digits) >= steps && entry.is_regular_file(ec)) std::filesystem::remove(entry.path(), ec);
  }
}

}  // namespace

std::filesystem::path write_vtk_series(const std::filesystem::path& dir, const std::string& stem, const ThermalModel& model,
                                       const ExportedNetwork& e, const std::vector<std::filesystem::path>& protected_inputs) {
  const int S = static_cast<int>(e.times_s.size());
  if (static_cast<int>(model.nodes.size()) != e.num_nodes() || e.temperature_K.cols() != S)
    throw InvalidInput("export vtk: the model has " + std::to_string(model.nodes.size()) + " nodes, the results " +
                       std::to_string(e.num_nodes()));
  for (int f = 0; f < model.mesh.num_faces(); ++f)
    if (model.mesh.face_node[f] < 0) throw InvalidInput("export vtk: face " + std::to_string(f) + " has no node");
  const Eigen::VectorXd area = face_areas(model.mesh.V, model.mesh.F);
  const Eigen::MatrixXd external = e.external_W();
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  // Every step file and the index replace an earlier series together; steps of a longer earlier
  // series under the same stem are removed after.
  AtomicFileSet series;
  for (int k = 0; k < S; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "_%04d.vtu", k);
    const std::string file = stem + name;
    // The node's absorbed power over its radiating area: what ParaView colours per face.
    const Eigen::VectorXd flux = external.col(k).cwiseQuotient(e.area_m2.cwiseMax(1e-300));
    series.add(dir / file, [&](std::ostream& out) { write_vtu(out, model, e, area, flux, k); }, protected_inputs);
    pvd += "    <DataSet timestep=\"" + real(e.times_s[k]) + "\" part=\"0\" file=\"" + xml_escaped(file) + "\"/>\n";
  }
  pvd += "  </Collection>\n</VTKFile>\n";
  const std::filesystem::path pvd_path = dir / (stem + ".pvd");
  series.add(pvd_path, [&](std::ostream& out) { out << pvd; }, protected_inputs);
  series.commit();
  remove_stale_steps(dir, stem, S);
  return pvd_path;
}

}  // namespace thermodec
