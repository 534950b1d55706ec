// PLY (Turk 1994), ascii and binary little/big endian. Hand-written: Debian ships no small
// PLY library (happly is not packaged) and vcglib's plylib reports neither line nor face on
// malformed input. Face properties `node`, `material`, `back_material` (ints, -1 = none) carry
// thermodec's attributes; `quality` (float) is read as the node id when there is no `node`
// property, because MeshLab stores per-face labels there. Names travel in comments:
// `comment thermodec node <id> <name>`, `comment thermodec material <id> <name>`.
#include <algorithm>
#include <cstring>
#include <fmt/format.h>
#include <iostream>
#include <map>

#include "mesh_formats.h"

namespace thermodec::mesh_formats {
namespace {

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

bool parse_type(std::string_view s, PlyType& t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},   {"uint8", PlyType::u8},
      {"short", PlyType::i16},  {"int16", PlyType::i16},   {"ushort", PlyType::u16}, {"uint16", PlyType::u16},
      {"int", PlyType::i32},    {"int32", PlyType::i32},   {"uint", PlyType::u32},   {"uint32", PlyType::u32},
      {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64}, {"float64", PlyType::f64}};
  for (const auto& [name, type] : names)
    if (s == name) { t = type; return true; }
  return false;
}

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::u8;
  PlyType type = PlyType::f32;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
  int find(std::string_view prop) const {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i].name == prop) return static_cast<int>(i);
    return -1;
  }
};

enum class Format { ascii, binary_le, binary_be };

bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

// Sequential value source over the body: one record (element instance) at a time.
class Body {
 public:
  Body(std::string_view data, std::size_t start, int start_line, Format format, const std::string& file)
      : data_(data), pos_(start), line_(start_line), format_(format), file_(file) {}

  // The record is named in errors as "<element> <index>", e.g. "face 12" (built only on error).
  void begin_record(const std::string& element, long long index) {
    element_ = &element;
    index_ = index;
    if (format_ != Format::ascii) return;
    word_ = 0;
    LineReader lines(data_.substr(pos_));
    std::string_view line;
    while (true) {
      if (!lines.next(line)) throw file_error(file_, "truncated PLY: file ends before " + what());
      ++line_;
      split_words_into(trim(line), words_);
      if (!words_.empty()) break;
    }
    pos_ += lines.position();
  }
  void end_record() {
    if (format_ == Format::ascii && word_ != words_.size())
      throw line_error(file_, line_, what() + " has " + std::to_string(words_.size()) + " values, the header declares " + std::to_string(word_));
  }

  double read(PlyType t) {
    if (format_ == Format::ascii) {
      if (word_ >= words_.size())
        throw line_error(file_, line_, what() + " has too few values (" + std::to_string(words_.size()) + ")");
      const std::string_view w = words_[word_++];
      double v;
      if (!parse_double(w, v)) throw line_error(file_, line_, what() + ": bad number " + field_text(w));
      return v;
    }
    const std::size_t n = type_size(t);
    if (pos_ + n > data_.size()) throw file_error(file_, "truncated binary PLY: data ends inside " + what());
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    if ((format_ == Format::binary_le) != host_is_little_endian()) std::reverse(b, b + n);
    switch (t) {
      case PlyType::i8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case PlyType::u8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
      case PlyType::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::f32: { float v; std::memcpy(&v, b, 4); return v; }
      case PlyType::f64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0.0;
  }

  std::string what() const { return *element_ + " " + std::to_string(index_); }
  std::string where() const {
    return format_ == Format::ascii ? file_ + ":" + std::to_string(line_) + ": " + what() : file_ + ": " + what();
  }

 private:
  std::string_view data_;
  std::size_t pos_;
  int line_;
  Format format_;
  const std::string& file_;
  const std::string* element_ = nullptr;
  long long index_ = 0;
  std::vector<std::string_view> words_;
  std::size_t word_ = 0;
};

// Turns file ids into indices of a compact name table: the ids named in comments plus the ids
// faces use, in ascending order. With the usual contiguous ids 0..n-1 this is the identity;
// sparse ids (e.g. MeshLab quality labels 3 and 70) give two names, not seventy-one.
void compact_ids(std::vector<std::string>& names, std::vector<Eigen::VectorXi*> ids,
                 const std::map<int, std::string>& named, const char* prefix) {
  std::map<int, int> index;
  for (const auto& [id, name] : named) index.emplace(id, 0);
  for (auto* v : ids)
    for (int f = 0; f < v->size(); ++f)
      if ((*v)[f] >= 0) index.emplace((*v)[f], 0);
  names.clear();
  for (auto& [id, position] : index) {
    position = static_cast<int>(names.size());
    auto it = named.find(id);
    names.push_back(it != named.end() ? it->second : fmt::format("{}_{}", prefix, id));
  }
  for (auto* v : ids)
    for (int f = 0; f < v->size(); ++f)
      if ((*v)[f] >= 0) (*v)[f] = index.at((*v)[f]);
}

}  // namespace

namespace {

struct PlyHeader {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::map<int, std::string> node_names, material_names;
};

// Reads the header up to and including `end_header`; `lines` is left at the first body byte.
PlyHeader parse_header(LineReader& lines, const std::string& file) {
  std::string_view raw;
  if (!lines.next(raw) || trim(raw) != "ply") throw line_error(file, 1, "not a PLY file (first line must be 'ply')");
  PlyHeader h;
  bool have_format = false;
  bool ended = false;
  while (!ended && lines.next(raw)) {
    const int ln = lines.line_number();
    const std::string_view line = trim(raw);
    const auto words = split_words(line);
    if (words.empty()) continue;
    const std::string_view key = words[0];
    if (key == "format") {
      if (words.size() < 2) throw line_error(file, ln, "format line without a format");
      if (words[1] == "ascii") h.format = Format::ascii;
      else if (words[1] == "binary_little_endian") h.format = Format::binary_le;
      else if (words[1] == "binary_big_endian") h.format = Format::binary_be;
      else throw line_error(file, ln, "unknown PLY format " + field_text(words[1]));
      have_format = true;
    } else if (key == "comment" || key == "obj_info") {
      if (words.size() >= 5 && words[1] == "thermodec" && (words[2] == "node" || words[2] == "material")) {
        long long id;
        if (!parse_long(words[3], id) || id < 0 || id > std::numeric_limits<int>::max())
          throw line_error(file, ln, "bad id in thermodec name comment");
        // The name is the rest of the line after the id (it may contain spaces).
        const std::size_t at = static_cast<std::size_t>(words[3].data() + words[3].size() - line.data());
        const std::string name(trim(line.substr(at)));
        (words[2] == "node" ? h.node_names : h.material_names)[static_cast<int>(id)] = name;
      }
    } else if (key == "element") {
      long long count;
      if (words.size() != 3 || !parse_long(words[2], count) || count < 0)
        throw line_error(file, ln, "expected 'element <name> <count>'");
      // A second `vertex` or `face` element would make faces index one vertex list while
      // another is stored: refuse rather than guess which one is meant.
      for (const Element& e : h.elements)
        if (e.name == words[1])
          throw line_error(file, ln, "element " + field_text(words[1]) + " declared twice");
      h.elements.push_back({std::string(words[1]), count, {}});
    } else if (key == "property") {
      if (h.elements.empty()) throw line_error(file, ln, "property before any element");
      Property p;
      if (words.size() == 5 && words[1] == "list") {
        p.is_list = true;
        if (!parse_type(words[2], p.count_type) || !parse_type(words[3], p.type))
          throw line_error(file, ln, "unknown PLY type in list property");
        p.name = std::string(words[4]);
      } else if (words.size() == 3) {
        if (!parse_type(words[1], p.type)) throw line_error(file, ln, "unknown PLY type " + field_text(words[1]));
        p.name = std::string(words[2]);
      } else {
        throw line_error(file, ln, "expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      h.elements.back().properties.push_back(p);
    } else if (key == "end_header") {
      ended = true;
    } else {
      throw line_error(file, ln, "unexpected PLY header line " + field_text(line));
    }
  }
  if (!ended) throw file_error(file, "truncated PLY: no 'end_header'");
  if (!have_format) throw file_error(file, "PLY header has no 'format' line");
  return h;
}

// Every record takes at least one byte (a binary scalar or list count, an ASCII digit), so
// a count above the bytes after the header is refused before any loop or allocation depends
// on it (a header may declare 9e18 records in a 1 KB file). Smaller shortfalls are reported
// where the data ends, naming the record.
void check_counts_fit(const PlyHeader& h, std::size_t body_bytes, const std::string& file) {
  for (const Element& e : h.elements) {
    if (e.count > 0 && e.properties.empty())
      throw file_error(file, "PLY element " + field_text(e.name) + " declares " + std::to_string(e.count) + " records but no properties");
    if (static_cast<unsigned long long>(e.count) > body_bytes)
      throw file_error(file, "truncated PLY: element " + field_text(e.name) + " declares " + std::to_string(e.count) +
                                 " records, more than the " + std::to_string(body_bytes) + " bytes after the header");
  }
}

}  // namespace

Mesh parse_ply(std::string_view data, const std::string& file) {
  if (trim(data).empty()) throw file_error(file, "empty file");
  LineReader lines(data);
  const PlyHeader header = parse_header(lines, file);
  const Format format = header.format;
  const std::vector<Element>& elements = header.elements;
  check_counts_fit(header, data.size() - lines.position(), file);

  // Binary data starts right after the "end_header" line's '\n'.
  Body body(data, lines.position(), lines.line_number(), format, file);
  std::vector<double> xyz;
  std::vector<std::array<int, 3>> tris;
  std::vector<long long> tri_face;  // face record index, for messages
  std::vector<double> tri_node, tri_material, tri_back, tri_quality;
  bool has_node = false, has_material = false, has_back = false, has_quality = false;
  long long num_vertices = -1;
  std::vector<long long> polygon;
  for (const Element& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int px = -1, py = -1, pz = -1, pidx = -1, pnode = -1, pmat = -1, pback = -1, pq = -1;
    if (is_vertex) {
      px = e.find("x"), py = e.find("y"), pz = e.find("z");
      if (px < 0 || py < 0 || pz < 0) throw file_error(file, "PLY vertex element lacks x, y or z");
      if (e.properties[px].is_list || e.properties[py].is_list || e.properties[pz].is_list)
        throw file_error(file, "PLY vertex x/y/z must be scalar properties");
      num_vertices = e.count;
      xyz.reserve(3 * static_cast<std::size_t>(std::min<long long>(e.count, static_cast<long long>(data.size()))));  // a header cannot make us allocate more than the file could hold
    }
    if (is_face) {
      pidx = e.find("vertex_indices");
      if (pidx < 0) pidx = e.find("vertex_index");
      if (pidx < 0 || !e.properties[pidx].is_list) throw file_error(file, "PLY face element lacks a 'vertex_indices' list");
      pnode = e.find("node"), pmat = e.find("material"), pback = e.find("back_material"), pq = e.find("quality");
      for (int p : {pnode, pmat, pback, pq})
        if (p >= 0 && e.properties[p].is_list) throw file_error(file, "PLY face property " + field_text(e.properties[p].name) + " must be scalar");
      has_node = pnode >= 0, has_material = pmat >= 0, has_back = pback >= 0, has_quality = pq >= 0;
    }
    for (long long r = 0; r < e.count; ++r) {
      body.begin_record(e.name, r);
      double pos[3] = {0, 0, 0};
      double node = -1, material = -1, back = -1, quality = -1;
      polygon.clear();
      for (int p = 0; p < static_cast<int>(e.properties.size()); ++p) {
        const Property& prop = e.properties[p];
        if (prop.is_list) {
          const double count = body.read(prop.count_type);
          if (!(count >= 0) || count != std::floor(count) || count > 1e6)
            throw InvalidInput(body.where() + ": bad list length " + fmt::format("{}", count));
          for (long long i = 0; i < static_cast<long long>(count); ++i) {
            const double v = body.read(prop.type);
            if (p == pidx) {
              if (v != std::floor(v)) throw InvalidInput(body.where() + ": vertex index " + fmt::format("{}", v) + " is not an integer");
              if (v < 0) throw InvalidInput(body.where() + ": negative vertex index " + fmt::format("{}", v));
              polygon.push_back(v > 9e18 ? std::numeric_limits<long long>::max() : static_cast<long long>(v));
            }
          }
          continue;
        }
        const double v = body.read(prop.type);
        if (p == px) pos[0] = v;
        else if (p == py) pos[1] = v;
        else if (p == pz) pos[2] = v;
        else if (p == pnode) node = v;
        else if (p == pmat) material = v;
        else if (p == pback) back = v;
        else if (p == pq) quality = v;
      }
      body.end_record();
      if (is_vertex) {
        for (double c : pos)
          if (!std::isfinite(c)) throw InvalidInput(body.where() + ": non-finite vertex coordinate");
        xyz.insert(xyz.end(), pos, pos + 3);
      }
      if (is_face) {
        if (polygon.size() < 3) throw InvalidInput(body.where() + ": face needs at least 3 vertices, has " + std::to_string(polygon.size()));
        for (double a : {node, material, back})
          if (a != std::floor(a) || a < -1 || a > std::numeric_limits<int>::max())
            throw InvalidInput(body.where() + ": node/material ids must be integers >= -1, got " + fmt::format("{}", a));
        for (std::size_t t = 1; t + 1 < polygon.size(); ++t) {
          tris.push_back({0, 0, 0});
          const long long c[3] = {polygon[0], polygon[t], polygon[t + 1]};
          for (int k = 0; k < 3; ++k) {
            if (num_vertices < 0 || c[k] >= num_vertices)
              throw InvalidInput(body.where() + ": vertex index " + std::to_string(c[k]) + " out of range (" +
                                 std::to_string(std::max(0ll, num_vertices)) + " vertices" +
                                 (num_vertices < 0 ? " declared before the faces)" : ")"));
            tris.back()[k] = static_cast<int>(c[k]);
          }
          tri_face.push_back(r);
          tri_node.push_back(node);
          tri_material.push_back(material);
          tri_back.push_back(back);
          tri_quality.push_back(quality);
        }
      }
    }
  }
  if (num_vertices < 0) throw file_error(file, "PLY file has no vertex element");
  if (tris.empty()) throw file_error(file, num_vertices == 0 ? "empty mesh: no vertices and no faces" : "no faces");

  Mesh mesh;
  const int nf = static_cast<int>(tris.size());
  mesh.V.resize(num_vertices, 3);
  for (long long i = 0; i < num_vertices; ++i)
    for (int k = 0; k < 3; ++k) mesh.V(i, k) = xyz[3 * i + k];
  mesh.F.resize(nf, 3);
  mesh.face_node = Eigen::VectorXi::Constant(nf, -1);
  mesh.face_material = Eigen::VectorXi::Constant(nf, -1);
  mesh.face_back_material = Eigen::VectorXi::Constant(nf, -1);
  bool quality_is_node_id = !has_node && has_quality;
  if (quality_is_node_id) {
    for (int f = 0; f < nf && quality_is_node_id; ++f) {
      const double q = tri_quality[f];
      quality_is_node_id = q == std::floor(q) && q >= -1 && q <= 1e6;
    }
    if (!quality_is_node_id)
      std::cerr << "thermodec: warning: " << file
                << ": face quality values are not integer node ids; quality ignored\n";
  }
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = tris[f][k];
    if (has_node) mesh.face_node[f] = static_cast<int>(tri_node[f]);
    else if (quality_is_node_id) mesh.face_node[f] = static_cast<int>(tri_quality[f]);
    if (has_material) mesh.face_material[f] = static_cast<int>(tri_material[f]);
    if (has_back) mesh.face_back_material[f] = static_cast<int>(tri_back[f]);
  }
  compact_ids(mesh.node_names, {&mesh.face_node}, header.node_names, "node");
  // Front and back materials share one name table.
  compact_ids(mesh.material_names, {&mesh.face_material, &mesh.face_back_material}, header.material_names, "material");
  return mesh;
}

void write_ply(std::ostream& out, const Mesh& mesh, bool binary) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::string header = "ply\n";
  header += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  header += "comment written by thermodec: node/material ids index the names below\n";
  for (std::size_t i = 0; i < mesh.node_names.size(); ++i)
    header += fmt::format("comment thermodec node {} {}\n", i, mesh.node_names[i]);
  for (std::size_t i = 0; i < mesh.material_names.size(); ++i)
    header += fmt::format("comment thermodec material {} {}\n", i, mesh.material_names[i]);
  header += fmt::format("element vertex {}\nproperty double x\nproperty double y\nproperty double z\n", nv);
  header += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", nf);
  // `quality` duplicates `node` so MeshLab can colour faces by node.
  header += "property int node\nproperty int material\nproperty int back_material\nproperty float quality\nend_header\n";
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  std::string buf;
  auto flush = [&] {
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    buf.clear();
  };
  if (!binary) {
    for (int i = 0; i < nv; ++i) {
      buf += fmt::format("{} {} {}\n", mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2));
      if (buf.size() > (1u << 20)) flush();
    }
    for (int f = 0; f < nf; ++f) {
      const int n = face_attribute(mesh.face_node, f);
      buf += fmt::format("3 {} {} {} {} {} {} {}\n", mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2), n,
                         face_attribute(mesh.face_material, f), face_attribute(mesh.face_back_material, f), n);
      if (buf.size() > (1u << 20)) flush();
    }
    flush();
    return;
  }
  auto put = [&](auto v) {
    unsigned char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    if (!host_is_little_endian()) std::reverse(b, b + sizeof(v));
    buf.append(reinterpret_cast<const char*>(b), sizeof(v));
  };
  buf.reserve(24ull * nv + 29ull * nf);
  for (int i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) put(mesh.V(i, k));
  for (int f = 0; f < nf; ++f) {
    put(std::uint8_t{3});
    for (int k = 0; k < 3; ++k) put(std::int32_t{mesh.F(f, k)});
    const int n = face_attribute(mesh.face_node, f);
    put(std::int32_t{n});
    put(std::int32_t{face_attribute(mesh.face_material, f)});
    put(std::int32_t{face_attribute(mesh.face_back_material, f)});
    put(static_cast<float>(n));
  }
  flush();
}

}  // namespace thermodec::mesh_formats
