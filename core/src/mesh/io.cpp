#include "thermodec/mesh/io.h"
#include "thermodec/mesh/remove_faces.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iostream>
#include <sstream>

#include "mesh_formats.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/printable.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/mesh/geometry_range.h"
#include "thermodec/mesh/weld.h"

namespace thermodec {
namespace {

enum class MeshFormat { obj, ply, stl, bdf };

MeshFormat format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return MeshFormat::obj;
  if (ext == ".ply") return MeshFormat::ply;
  if (ext == ".stl") return MeshFormat::stl;
  if (ext == ".bdf" || ext == ".nas" || ext == ".dat") return MeshFormat::bdf;
  throw InvalidInput(path.string() + ": unknown mesh format '" + ext + "' (expected .obj, .ply, .stl, or NASTRAN .bdf .nas .dat)");
}

std::string read_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) throw IOError(path.string() + ": is a folder, not a mesh file");
  if (!std::filesystem::exists(status)) throw IOError(path.string() + ": cannot open for reading (no such file)");
  if (!std::filesystem::is_regular_file(status))
    throw IOError(path.string() + ": not a regular file (a device, FIFO or socket); mesh files must be regular files");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw IOError(path.string() + ": cannot read its size: " + ec.message());
  if (size > kMaxMeshFileBytes)
    throw IOError(path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                  std::to_string(kMaxMeshFileBytes) + "-byte limit for mesh files");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError(path.string() + ": cannot open for reading");
  // Read at most the size checked above (+1 to notice a file that grew meanwhile).
  std::string data(static_cast<std::size_t>(size) + 1, '\0');
  in.read(data.data(), static_cast<std::streamsize>(data.size()));
  if (in.bad()) throw IOError(path.string() + ": read failed");
  data.resize(static_cast<std::size_t>(in.gcount()));
  if (data.size() > size) throw IOError(path.string() + ": the file grew while being read");
  return data;
}

std::string list_faces(const std::vector<int>& faces) {
  std::string s;
  const std::size_t shown = std::min<std::size_t>(faces.size(), 10);
  for (std::size_t i = 0; i < shown; ++i) s += (i ? ", " : "") + std::to_string(faces[i]);
  if (faces.size() > shown) s += ", ... (" + std::to_string(faces.size()) + " in all)";
  return s;
}

void check_writable(const Mesh& mesh) {
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  if (mesh.F.cols() != 3 && nf > 0) throw InvalidInput("cannot write mesh: F must have 3 columns");
  if (mesh.V.cols() != 3 && nv > 0) throw InvalidInput("cannot write mesh: V must have 3 columns");
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= nv)
        throw InvalidInput("cannot write mesh: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(mesh.F(f, k)) + " out of range (" + std::to_string(nv) + " vertices)");
  for (Eigen::Index i = 0; i < mesh.V.size(); ++i)
    if (!std::isfinite(mesh.V.data()[i])) throw InvalidInput("cannot write mesh: non-finite vertex coordinate");
  auto check = [&](const Eigen::VectorXi& a, const std::vector<std::string>& names, const char* what) {
    if (a.size() != 0 && a.size() != nf)
      throw InvalidInput(std::string("cannot write mesh: ") + what + " has " + std::to_string(a.size()) +
                         " entries for " + std::to_string(nf) + " faces");
    for (int f = 0; f < a.size(); ++f)
      if (a[f] < -1 || a[f] >= static_cast<int>(names.size()))
        throw InvalidInput(std::string("cannot write mesh: face ") + std::to_string(f) + " has " + what + " " +
                           std::to_string(a[f]) + " outside its name list");
  };
  check(mesh.face_node, mesh.node_names, "face_node");
  check(mesh.face_material, mesh.material_names, "face_material");
  check(mesh.face_back_material, mesh.material_names, "face_back_material");
  for (const auto& n : mesh.node_names) mesh_formats::check_name_writable(n, "node");
  for (const auto& n : mesh.material_names) mesh_formats::check_name_writable(n, "material");
}

// The docs and model.json forbid control characters in names: they would reach terminals and
// other tools' input files as escape sequences.
void check_names(const Mesh& mesh, const std::string& file) {
  auto check = [&](const std::vector<std::string>& names, const char* kind) {
    for (const auto& n : names)
      if (has_control_characters(n))
        throw InvalidInput(file + ": " + kind + " name '" + printable(n, 80) +
                           "' contains control characters (escape sequences, direction overrides); names must be plain text");
  };
  check(mesh.node_names, "node");
  check(mesh.material_names, "material");
}

}  // namespace

Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options, MeshReadReport& report) {
  const MeshFormat format = format_of(path);
  const std::string data = read_bytes(path);
  const std::string file = path.string();
  if (data.empty()) throw InvalidInput(file + ": empty file");
  Mesh mesh;
  switch (format) {
    case MeshFormat::obj: mesh = mesh_formats::parse_obj(data, file); break;
    case MeshFormat::ply: mesh = mesh_formats::parse_ply(data, file); break;
    case MeshFormat::stl: mesh = mesh_formats::parse_stl(data, file); break;
    case MeshFormat::bdf: mesh = mesh_formats::parse_bdf(data, file); break;
  }
  check_geometry_range(mesh.V, mesh.F, file);
  check_names(mesh, file);
  report = MeshReadReport{};
  double tolerance = options.weld_tolerance;
  if (std::isnan(tolerance)) throw InvalidInput("weld tolerance is NaN");
  if (format == MeshFormat::stl) tolerance = std::max(tolerance, 0.0);
  if (tolerance >= 0.0) report.welded_vertices = weld_mesh_vertices(mesh.V, mesh.F, tolerance);
  report.degenerate_faces = degenerate_faces(mesh.V, mesh.F);
  if (options.drop_degenerate_faces && !report.degenerate_faces.empty()) {
    if (report.degenerate_faces.size() == static_cast<std::size_t>(mesh.num_faces()))
      throw InvalidInput(file + ": all " + std::to_string(mesh.num_faces()) + " faces are degenerate (zero area)");
    std::vector<char> keep(mesh.num_faces(), 1);
    for (int f : report.degenerate_faces) keep[f] = 0;
    remove_faces(mesh, keep);
    report.degenerate_faces_dropped = true;
  }
  return mesh;
}

Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options) {
  MeshReadReport report;
  Mesh mesh = read_mesh(path, options, report);
  if (report.degenerate_faces_dropped)
    std::cerr << "thermodec: warning: " << path.string() << ": dropped " << report.degenerate_faces.size()
              << " degenerate (zero-area) face(s), triangle indices " << list_faces(report.degenerate_faces) << "\n";
  return mesh;
}

void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const MeshWriteOptions& options) {
  const MeshFormat format = format_of(path);
  if (format == MeshFormat::bdf)
    throw InvalidInput(path.string() + ": NASTRAN bulk data is written by `thermodec export --format nastran`");
  check_writable(mesh);
  write_file_atomically(path, [&](std::ostream& out) {
    switch (format) {
      case MeshFormat::obj: mesh_formats::write_obj(out, mesh); break;
      case MeshFormat::ply: mesh_formats::write_ply(out, mesh, options.binary); break;
      case MeshFormat::stl: mesh_formats::write_stl(out, mesh, options.binary); break;
      case MeshFormat::bdf: break;  // refused above
    }
  }, options.protected_inputs);
}

}  // namespace thermodec
