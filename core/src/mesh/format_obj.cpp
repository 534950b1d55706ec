// Wavefront OBJ. Hand-written rather than tinyobjloader (Debian's libtinyobjloader-dev)
// because thermodec needs what that loader does not give: line numbers in every error, and
// `usemtl` names kept even when no .mtl file exists (tinyobjloader maps unknown materials to
// -1 with a warning). Only the subset a triangle mesh needs is read: v, f, g, o, usemtl.
#include <array>
#include <fmt/format.h>
#include <limits>
#include <map>

#include "mesh_formats.h"

namespace thermodec::mesh_formats {
namespace {
// Comment directives for what OBJ cannot express (other tools ignore them): two-sidedness,
// and the full ordered name tables (so ids and unused names survive a round trip).
constexpr std::string_view kBackMaterialDirective = "#thermodec back_material";
constexpr std::string_view kNodeDirective = "#thermodec node ";
constexpr std::string_view kMaterialDirective = "#thermodec material ";

int intern(std::map<std::string, int, std::less<>>& ids, std::vector<std::string>& names,
           std::string_view name) {
  auto it = ids.find(name);
  if (it != ids.end()) return it->second;
  const int id = static_cast<int>(names.size());
  names.emplace_back(name);
  ids.emplace(std::string(name), id);
  return id;
}
}  // namespace

Mesh parse_obj(std::string_view data, const std::string& file) {
  std::vector<double> xyz;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> tri_line, tri_node, tri_material, tri_back;
  Mesh mesh;
  std::map<std::string, int, std::less<>> node_ids, material_ids;
  int node = -1, material = -1, back = -1;

  LineReader lines(data);
  std::string_view raw;
  std::vector<long long> polygon;
  while (lines.next(raw)) {
    const int ln = lines.line_number();
    const std::string_view line = trim(raw);
    if (line.empty()) continue;
    // A NUL byte would travel into group and material names and on into every written file.
    if (line.find('\0') != std::string_view::npos) throw line_error(file, ln, "NUL byte in the line (not a text OBJ file?)");
    if (line.front() == '#') {
      if (line.substr(0, kBackMaterialDirective.size()) == kBackMaterialDirective) {
        const std::string_view name = trim(line.substr(kBackMaterialDirective.size()));
        back = (name.empty() || name == "none") ? -1 : intern(material_ids, mesh.material_names, name);
      } else if (line.substr(0, kNodeDirective.size()) == kNodeDirective) {
        intern(node_ids, mesh.node_names, trim(line.substr(kNodeDirective.size())));
      } else if (line.substr(0, kMaterialDirective.size()) == kMaterialDirective) {
        intern(material_ids, mesh.material_names, trim(line.substr(kMaterialDirective.size())));
      }
      continue;
    }
    std::size_t k = 0;
    while (k < line.size() && !is_space(line[k])) ++k;
    const std::string_view key = line.substr(0, k);
    const std::string_view rest = trim(line.substr(k));
    if (key == "v") {
      const auto words = split_words(rest);
      if (words.size() < 3) throw line_error(file, ln, "vertex needs 3 coordinates, found " + std::to_string(words.size()));
      for (int c = 0; c < 3; ++c) {
        double x;
        if (!parse_double(words[c], x)) throw line_error(file, ln, "bad vertex coordinate " + field_text(words[c]));
        if (!std::isfinite(x)) throw line_error(file, ln, "non-finite vertex coordinate " + field_text(words[c]));
        xyz.push_back(x);
      }
      // Optional w or r g b colour values are not needed and ignored.
    } else if (key == "f") {
      const auto words = split_words(rest);
      if (words.size() < 3) throw line_error(file, ln, "face needs at least 3 vertices, found " + std::to_string(words.size()));
      polygon.clear();
      const long long nv = static_cast<long long>(xyz.size() / 3);
      for (auto w : words) {
        const std::string_view index_text = w.substr(0, w.find('/'));
        long long i;
        if (!parse_long(index_text, i)) throw line_error(file, ln, "bad vertex index " + field_text(w));
        // v, v/vt, v//vn or v/vt/vn: the texture and normal indices are not used, but anything
        // else after the vertex index (`1/a`) is a malformed file, not something to skip.
        if (index_text.size() < w.size()) {
          std::string_view rest_of_index = w.substr(index_text.size() + 1);
          int parts = 0;
          while (true) {
            const std::string_view part = rest_of_index.substr(0, rest_of_index.find('/'));
            long long ignored;
            if (++parts > 2 || (!part.empty() && !parse_long(part, ignored)))
              throw line_error(file, ln, "bad face corner " + field_text(w) + " (expected v, v/vt, v//vn or v/vt/vn)");
            if (part.size() == rest_of_index.size()) break;
            rest_of_index = rest_of_index.substr(part.size() + 1);
          }
        }
        if (i == 0) throw line_error(file, ln, "vertex index 0 (OBJ indices start at 1)");
        if (i < 0) {
          // Relative index: -1 is the latest vertex defined above this line (compared as
          // i < -nv: negating i overflows for the most negative integer).
          if (i < -nv) throw line_error(file, ln, "relative vertex index " + std::to_string(i) + " points before the first vertex (" + std::to_string(nv) + " defined so far)");
          polygon.push_back(nv + i);
        } else {
          // Faces may only use vertices defined above them, as relative indices already must.
          if (i > nv)
            throw line_error(file, ln, "vertex index " + std::to_string(i) + " out of range (" + std::to_string(nv) +
                                           " vertices defined above this face; faces may only use earlier vertices)");
          polygon.push_back(i - 1);
        }
      }
      for (std::size_t t = 1; t + 1 < polygon.size(); ++t) {
        tris.push_back({static_cast<int>(polygon[0]), static_cast<int>(polygon[t]), static_cast<int>(polygon[t + 1])});
        tri_line.push_back(ln);
        tri_node.push_back(node);
        tri_material.push_back(material);
        tri_back.push_back(back);
      }
    } else if (key == "g" || key == "o") {
      // `o` and `g` both name the current thermal node; the latest one wins. A bare `g`
      // returns to "no group".
      node = rest.empty() ? -1 : intern(node_ids, mesh.node_names, rest);
    } else if (key == "usemtl") {
      material = rest.empty() ? -1 : intern(material_ids, mesh.material_names, rest);
    }
    // vt, vn, s, l, p, mtllib, ...: not needed for a thermal mesh.
  }

  const long long nv = static_cast<long long>(xyz.size() / 3);
  if (tris.empty()) {
    if (nv == 0) throw file_error(file, "empty mesh: no vertices and no faces");
    throw file_error(file, "no faces (" + std::to_string(nv) + " vertices but no 'f' lines)");
  }
  const int nf = static_cast<int>(tris.size());
  mesh.V.resize(nv, 3);
  for (long long i = 0; i < nv; ++i)
    for (int c = 0; c < 3; ++c) mesh.V(i, c) = xyz[3 * i + c];
  mesh.F.resize(nf, 3);
  mesh.face_node.resize(nf);
  mesh.face_material.resize(nf);
  mesh.face_back_material.resize(nf);
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      if (tris[f][c] >= nv)
        throw line_error(file, tri_line[f], "vertex index " + std::to_string(tris[f][c] + 1) + " out of range (the file has " + std::to_string(nv) + " vertices)");
      mesh.F(f, c) = tris[f][c];
    }
    mesh.face_node[f] = tri_node[f];
    mesh.face_material[f] = tri_material[f];
    mesh.face_back_material[f] = tri_back[f];
  }
  return mesh;
}

void write_obj(std::ostream& out, const Mesh& mesh) {
  fmt::memory_buffer buf;
  fmt::format_to(std::back_inserter(buf), "# thermodec mesh: {} vertices, {} triangles\n",
                 mesh.num_vertices(), mesh.num_faces());
  for (const auto& name : mesh.node_names) fmt::format_to(std::back_inserter(buf), "{}{}\n", kNodeDirective, name);
  for (const auto& name : mesh.material_names) fmt::format_to(std::back_inserter(buf), "{}{}\n", kMaterialDirective, name);
  for (int i = 0; i < mesh.num_vertices(); ++i)
    fmt::format_to(std::back_inserter(buf), "v {} {} {}\n", mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2));
  int node = -1, material = -1, back = -1;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int n = face_attribute(mesh.face_node, f), m = face_attribute(mesh.face_material, f),
              b = face_attribute(mesh.face_back_material, f);
    if (f == 0 || n != node) {
      if (n >= 0) fmt::format_to(std::back_inserter(buf), "g {}\n", mesh.node_names[n]);
      else if (f > 0) fmt::format_to(std::back_inserter(buf), "g\n");
      node = n;
    }
    if (f == 0 || m != material) {
      if (m >= 0) fmt::format_to(std::back_inserter(buf), "usemtl {}\n", mesh.material_names[m]);
      else if (f > 0) fmt::format_to(std::back_inserter(buf), "usemtl\n");
      material = m;
    }
    if (f == 0 ? b >= 0 : b != back) {
      fmt::format_to(std::back_inserter(buf), "{} {}\n", kBackMaterialDirective,
                     b >= 0 ? mesh.material_names[b] : std::string("none"));
    }
    back = b;
    fmt::format_to(std::back_inserter(buf), "f {} {} {}\n", mesh.F(f, 0) + 1, mesh.F(f, 1) + 1, mesh.F(f, 2) + 1);
    if (buf.size() > (1u << 20)) {
      out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  }
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

}  // namespace thermodec::mesh_formats
