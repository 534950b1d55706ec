// STL, ascii and binary. STL stores every triangle's corners separately, so read_mesh always
// welds its vertices. In ascii files with several `solid` blocks, the solid names become
// thermal nodes (a single solid's name is usually just an exporter's label and is ignored).
#include <array>
#include <cstring>
#include <fmt/format.h>
#include <map>

#include "mesh_formats.h"
#include "thermodec/mesh/face_geometry.h"

namespace thermodec::mesh_formats {
namespace {

bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

template <typename T>
T read_le(const char* p) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (!host_is_little_endian())
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

template <typename T>
void write_le(std::string& out, T v) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  if (!host_is_little_endian())
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

bool starts_with_solid(std::string_view data) {
  const std::string_view t = trim(data.substr(0, 512));
  return t.substr(0, 5) == "solid" && (t.size() == 5 || is_space(t[5]) || t[5] == '\n' || t[5] == '\r');
}

Mesh parse_binary_stl(std::string_view data, const std::string& file) {
  if (data.size() < 84)
    throw file_error(file, "truncated binary STL: " + std::to_string(data.size()) + " bytes, the header alone needs 84");
  const std::uint32_t n = read_le<std::uint32_t>(data.data() + 80);
  if (n == 0) throw file_error(file, "empty mesh: binary STL with 0 triangles");
  const std::uint64_t need = 84ull + 50ull * n;
  if (data.size() < need) {
    const std::uint64_t complete = (data.size() - 84) / 50;
    throw file_error(file, "truncated binary STL: header announces " + std::to_string(n) +
                               " triangles, data ends inside face " + std::to_string(complete));
  }
  Mesh mesh;
  mesh.V.resize(3ll * n, 3);
  mesh.F.resize(n, 3);
  for (std::uint32_t f = 0; f < n; ++f) {
    const char* p = data.data() + 84 + 50ull * f + 12;  // skip the stored normal: recomputed from corners
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) {
        const float x = read_le<float>(p + 12 * c + 4 * k);
        if (!std::isfinite(x)) throw file_error(file, "face " + std::to_string(f) + ": non-finite vertex coordinate");
        mesh.V(3ll * f + c, k) = x;
      }
      mesh.F(f, c) = static_cast<int>(3 * f + c);
    }
  }
  mesh.face_node = Eigen::VectorXi::Constant(n, -1);
  mesh.face_material = Eigen::VectorXi::Constant(n, -1);
  mesh.face_back_material = Eigen::VectorXi::Constant(n, -1);
  return mesh;
}

Mesh parse_ascii_stl(std::string_view data, const std::string& file) {
  std::vector<std::array<double, 3>> corners;
  std::vector<int> solid_of_face;
  std::vector<std::string> solid_names;
  LineReader lines(data);
  std::string_view raw;
  enum class State { outside, in_solid, in_facet, in_loop } state = State::outside;
  int corners_in_loop = 0;
  while (lines.next(raw)) {
    const int ln = lines.line_number();
    const auto words = split_words(trim(raw));
    if (words.empty()) continue;
    const std::string_view key = words[0];
    auto expect = [&](const char* what) {
      return line_error(file, ln, std::string("expected ") + what + ", found " + field_text(trim(raw)));
    };
    switch (state) {
      case State::outside:
        if (key != "solid") throw expect("'solid'");
        solid_names.emplace_back(trim(trim(raw).substr(5)));
        state = State::in_solid;
        break;
      case State::in_solid:
        if (key == "endsolid") { state = State::outside; break; }
        if (key != "facet") throw expect("'facet' or 'endsolid'");
        state = State::in_facet;
        break;
      case State::in_facet:
        if (key == "endfacet") {
          if (corners_in_loop != 3) throw expect("'outer loop' with 3 vertices before 'endfacet'");
          corners_in_loop = 0;
          state = State::in_solid;
          break;
        }
        if (key != "outer" || corners_in_loop != 0) throw expect("'outer loop'");
        state = State::in_loop;
        break;
      case State::in_loop:
        if (key == "endloop") {
          if (corners_in_loop != 3) throw line_error(file, ln, "facet has " + std::to_string(corners_in_loop) + " vertices, STL needs 3");
          state = State::in_facet;
          break;
        }
        if (key != "vertex") throw expect("'vertex' or 'endloop'");
        if (words.size() != 4) throw line_error(file, ln, "vertex needs 3 coordinates");
        if (corners_in_loop == 3) throw line_error(file, ln, "facet has more than 3 vertices");
        {
          std::array<double, 3> p;
          for (int k = 0; k < 3; ++k) {
            if (!parse_double(words[1 + k], p[k])) throw line_error(file, ln, "bad vertex coordinate " + field_text(words[1 + k]));
            if (!std::isfinite(p[k])) throw line_error(file, ln, "non-finite vertex coordinate " + field_text(words[1 + k]));
          }
          corners.push_back(p);
        }
        if (++corners_in_loop == 3) solid_of_face.push_back(static_cast<int>(solid_names.size()) - 1);
        break;
    }
  }
  if (state != State::outside) throw file_error(file, "truncated ascii STL: ends inside a " + std::string(state == State::in_solid ? "solid" : "facet"));
  const int nf = static_cast<int>(solid_of_face.size());
  if (nf == 0) throw file_error(file, "empty mesh: STL without facets");
  Mesh mesh;
  mesh.V.resize(3 * nf, 3);
  mesh.F.resize(nf, 3);
  for (int i = 0; i < 3 * nf; ++i)
    for (int k = 0; k < 3; ++k) mesh.V(i, k) = corners[i][k];
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) mesh.F(f, c) = 3 * f + c;
  mesh.face_node = Eigen::VectorXi::Constant(nf, -1);
  mesh.face_material = Eigen::VectorXi::Constant(nf, -1);
  mesh.face_back_material = Eigen::VectorXi::Constant(nf, -1);
  if (solid_names.size() > 1) {
    std::map<std::string, int> ids;
    for (int f = 0; f < nf; ++f) {
      const std::string& name = solid_names[solid_of_face[f]];
      if (name.empty()) continue;
      auto [it, added] = ids.emplace(name, static_cast<int>(mesh.node_names.size()));
      if (added) mesh.node_names.push_back(name);
      mesh.face_node[f] = it->second;
    }
  }
  return mesh;
}
}  // namespace

Mesh parse_stl(std::string_view data, const std::string& file) {
  if (trim(data).empty()) throw file_error(file, "empty file");
  // Some binary exporters also begin their 80-byte header with "solid": a size that matches
  // the binary layout exactly decides for binary.
  if (data.size() >= 84) {
    const std::uint32_t n = read_le<std::uint32_t>(data.data() + 80);
    if (data.size() == 84ull + 50ull * n) return parse_binary_stl(data, file);
  }
  if (starts_with_solid(data)) return parse_ascii_stl(data, file);
  return parse_binary_stl(data, file);
}

void write_stl(std::ostream& out, const Mesh& mesh, bool binary) {
  const Eigen::MatrixXd N = face_normals(mesh.V, mesh.F);
  const int nf = mesh.num_faces();
  if (binary) {
    std::string buf;
    buf.reserve(84 + 50ull * nf);
    std::string header = "thermodec binary STL";
    header.resize(80, ' ');
    buf += header;
    write_le<std::uint32_t>(buf, static_cast<std::uint32_t>(nf));
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) write_le<float>(buf, static_cast<float>(N(f, k)));
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) write_le<float>(buf, static_cast<float>(mesh.V(mesh.F(f, c), k)));
      write_le<std::uint16_t>(buf, 0);
    }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    return;
  }
  // One solid per run of faces of the same node, so the face order survives a round trip.
  fmt::memory_buffer buf;
  auto out_it = std::back_inserter(buf);
  int f = 0;
  do {
    const int node = face_attribute(mesh.face_node, f);
    const std::string name = node >= 0 ? mesh.node_names[node] : std::string();
    fmt::format_to(out_it, "solid {}\n", name);
    for (; f < nf && face_attribute(mesh.face_node, f) == node; ++f) {
      fmt::format_to(out_it, "  facet normal {} {} {}\n    outer loop\n", N(f, 0), N(f, 1), N(f, 2));
      for (int c = 0; c < 3; ++c)
        fmt::format_to(out_it, "      vertex {} {} {}\n", mesh.V(mesh.F(f, c), 0), mesh.V(mesh.F(f, c), 1), mesh.V(mesh.F(f, c), 2));
      fmt::format_to(out_it, "    endloop\n  endfacet\n");
    }
    fmt::format_to(out_it, "endsolid {}\n", name);
  } while (f < nf);
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

}  // namespace thermodec::mesh_formats
