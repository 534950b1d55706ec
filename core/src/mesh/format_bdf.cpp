// NASTRAN bulk data reader (MSC/NX Quick Reference Guide card layouts). Only the cards that
// carry a radiating surface are read; everything else is listed once and skipped, because a
// structural deck holds many cards (CBAR, CONM2, SPC, ...) that have no meaning for radiation.
#include "thermodec/mesh/format_bdf.h"

#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "mesh_formats.h"

namespace thermodec {
namespace mesh_formats {
namespace {

// One card with its fields (name excluded, trimmed, continuation markers dropped).
struct Card {
  std::string name;
  std::vector<std::string> fields;
  int line = 0;
};

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

std::string expand_tabs(std::string_view line) {
  std::string out;
  for (char c : line) {
    if (c == '\t') do out += ' '; while (out.size() % 8 != 0);
    else out += c;
  }
  return out;
}

// Fields of one physical line. Free field: commas. Fixed: 8 columns for the name, then 8
// small fields (or 4 large ones for a `*` card) and a continuation field that is dropped.
std::vector<std::string> line_fields(const std::string& line, bool large) {
  std::vector<std::string> f;
  if (line.find(',') != std::string::npos) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      f.emplace_back(trim(std::string_view(line).substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (f.size() >= 10) f.resize(9);  // field 10: continuation marker
    return f;
  }
  auto column = [&](std::size_t a, std::size_t w) {
    return a < line.size() ? std::string(trim(std::string_view(line).substr(a, w))) : std::string();
  };
  f.push_back(column(0, 8));
  const std::size_t width = large ? 16 : 8, count = large ? 4 : 8;
  for (std::size_t k = 0; k < count; ++k) f.push_back(column(8 + k * width, width));
  while (f.size() > 1 && f.back().empty()) f.pop_back();
  return f;
}

struct Deck {
  std::vector<Card> cards;
  // From `$ thermodec` comments: names by PID and MID, back materials of two-sided elements by EID.
  std::map<long long, std::string> node_names, material_names, back_materials;
  bool ended = false;  // ENDDATA seen
};

// `$ thermodec node PID NAME`, `$ thermodec material MID NAME`, `$ thermodec back_material EID
// NAME`: what exchange/write_nastran_bulk.h keeps beyond the cards.
void read_name_comment(std::string_view line, Deck& deck) {
  const auto w = split_words(line.substr(1));
  long long id = 0;
  if (w.size() < 4 || w[0] != "thermodec" || !parse_long(w[2], id)) return;
  const auto rest = trim(line.substr(static_cast<std::size_t>(w[3].data() - line.data())));
  if (w[1] == "node") deck.node_names[id] = std::string(rest);
  if (w[1] == "material") deck.material_names[id] = std::string(rest);
  if (w[1] == "back_material") deck.back_materials[id] = std::string(rest);
}

Deck read_deck(std::string_view data, const std::string& file) {
  Deck deck;
  // Executive and case control come before BEGIN BULK; a file without it is bulk data only.
  bool in_bulk = upper(data).find("BEGIN BULK") == std::string::npos;
  LineReader reader(data);
  std::string_view raw;
  bool open = false;
  bool open_large = false;
  while (reader.next(raw)) {
    const std::string line = expand_tabs(raw);
    const std::string_view t = trim(line);
    if (!in_bulk) {
      if (upper(t).rfind("BEGIN BULK", 0) == 0) in_bulk = true;
      continue;
    }
    if (t.empty()) continue;
    if (t.front() == '$') { read_name_comment(t, deck); continue; }
    const std::string head = upper(t.substr(0, std::min<std::size_t>(t.size(), 8)));
    if (head.rfind("ENDDATA", 0) == 0) {
      deck.ended = true;
      break;
    }
    const bool continuation = line[0] == '+' || line[0] == '*' || line[0] == ',' || line[0] == ' ';
    if (continuation) {
      if (!open) throw line_error(file, reader.line_number(), "continuation line without a card before it");
      auto f = line_fields(line, line[0] == '*' || open_large);
      auto& fields = deck.cards.back().fields;
      fields.insert(fields.end(), f.begin() + 1, f.end());
      continue;
    }
    if (upper(t).rfind("INCLUDE", 0) == 0)
      throw line_error(file, reader.line_number(), "INCLUDE is not supported: merge the included file into one deck");
    auto f = line_fields(line, false);
    std::string name = upper(f[0]);
    open_large = !name.empty() && name.back() == '*';
    if (open_large) {
      name.pop_back();
      if (line.find(',') == std::string::npos) f = line_fields(line, true);
    }
    deck.cards.push_back({name, std::vector<std::string>(f.begin() + 1, f.end()), reader.line_number()});
    open = true;
  }
  return deck;
}

// NASTRAN reals may omit the E ("1.5-3", "7.+2") or use D.
bool parse_nastran_real(std::string s, double& value) {
  for (char& c : s)
    if (c == 'D' || c == 'd') c = 'E';
  if (s.find_first_of("eE") == std::string::npos) {
    const std::size_t sign = s.find_first_of("+-", 1);
    if (sign != std::string::npos) s.insert(sign, "E");
  }
  return parse_double(s, value) && std::isfinite(value);
}

class Fields {
 public:
  Fields(const Card& card, const std::string& file) : card_(card), file_(file) {}
  const std::string& raw(std::size_t k) const {
    static const std::string empty;
    return k < card_.fields.size() ? card_.fields[k] : empty;
  }
  // Field k counts from 2 as in the Quick Reference Guide (field 1 is the card name).
  long long integer(std::size_t k, const char* what, std::optional<long long> blank = std::nullopt) const {
    const std::string& s = raw(k - 2);
    long long v = 0;
    if (s.empty() && blank) return *blank;
    if (s.empty()) fail(k, what, "is blank");
    if (!parse_long(s, v)) fail(k, what, "is not an integer: " + field_text(s));
    return v;
  }
  double real(std::size_t k, const char* what) const {
    const std::string& s = raw(k - 2);
    double v = 0.0;
    if (s.empty()) fail(k, what, "is blank");
    if (!parse_nastran_real(s, v)) fail(k, what, "is not a number: " + field_text(s));
    return v;
  }
  [[noreturn]] void fail(std::size_t k, const char* what, const std::string& why) const {
    throw line_error(file_, card_.line, label() + ": field " + std::to_string(k) + " (" + what + ") " + why);
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw line_error(file_, card_.line, label() + ": " + why);
  }
  std::string label() const { return printable(card_.name, 16) + " " + printable(raw(0), 16); }

 private:
  const Card& card_;
  const std::string& file_;
};

Deck load_deck(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError(path.string() + ": cannot open for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return read_deck(s.str(), path.string());
}

std::string material_name(const Deck& deck, long long mid) {
  const auto it = deck.material_names.find(mid);
  return it != deck.material_names.end() ? it->second : "MAT" + std::to_string(mid);
}

}  // namespace

Mesh parse_bdf(std::string_view data, const std::string& file) {
  const Deck deck = read_deck(data, file);
  std::map<long long, int> vertex_of_grid;
  std::vector<Eigen::Vector3d> points;
  std::map<long long, long long> material_of_property;
  struct Element { long long eid, pid; std::vector<long long> grids; const Card* card; };
  std::vector<Element> elements;
  std::map<std::string, int> skipped;
  std::set<long long> element_ids;
  for (const Card& c : deck.cards) {
    const Fields f(c, file);
    if (c.name == "GRID") {
      const long long id = f.integer(2, "ID");
      if (id <= 0) f.fail(2, "ID", "must be a positive integer");
      if (f.integer(3, "CP", 0) != 0) f.fail("coordinate system CP " + f.raw(1) + " is not supported (GRIDs must be in the basic system)");
      if (!vertex_of_grid.emplace(id, static_cast<int>(points.size())).second) f.fail("GRID " + std::to_string(id) + " is defined twice");
      points.emplace_back(f.real(4, "X1"), f.real(5, "X2"), f.real(6, "X3"));
    } else if (c.name == "CTRIA3" || c.name == "CTRIAR" || c.name == "CQUAD4" || c.name == "CQUADR") {
      const long long eid = f.integer(2, "EID");
      if (eid <= 0) f.fail(2, "EID", "must be a positive integer");
      if (!element_ids.insert(eid).second) f.fail("element " + std::to_string(eid) + " is defined twice");
      Element e{eid, f.integer(3, "PID", eid), {}, &c};  // blank PID = EID (QRG)
      const int corners = c.name[1] == 'T' ? 3 : 4;
      for (int k = 0; k < corners; ++k) e.grids.push_back(f.integer(4 + k, "G"));
      elements.push_back(std::move(e));
    } else if (c.name == "PSHELL") {
      material_of_property[f.integer(2, "PID")] = f.integer(3, "MID1", -1);
    } else if (c.name != "RADM") {
      ++skipped[c.name];
    }
  }
  if (!skipped.empty()) {
    std::string list;
    for (const auto& [name, n] : skipped) {
      if (list.size() > 400) {
        list += ", ...";
        break;
      }
      list += (list.empty() ? "" : ", ") + printable(name, 16) + " (" + std::to_string(n) + ")";
    }
    std::cerr << "thermodec: warning: " << file << ": skipped cards that carry no radiating surface: " << list << "\n";
  }
  if (elements.empty()) throw file_error(file, "no CTRIA3/CQUAD4 elements (a radiating surface is needed)");
  if (!deck.ended)
    std::cerr << "thermodec: warning: " << file << ": no ENDDATA card: the deck may have been cut short; check that every element is there\n";

  Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) mesh.V.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  std::map<long long, int> node_of_pid, material_of_mid;
  for (const Element& e : elements) node_of_pid.emplace(e.pid, 0);
  // Property ids that carry the same node name (one node, several coatings) are one node.
  std::map<std::string, int> node_of_name;
  for (auto& [pid, index] : node_of_pid) {
    const auto it = deck.node_names.find(pid);
    const std::string name = it != deck.node_names.end() ? it->second : "PID" + std::to_string(pid);
    const auto [at, added] = node_of_name.emplace(name, static_cast<int>(mesh.node_names.size()));
    if (added) mesh.node_names.push_back(name);
    index = at->second;
  }
  for (const auto& [pid, mid] : material_of_property)
    if (mid > 0 && node_of_pid.count(pid)) material_of_mid.emplace(mid, 0);
  for (auto& [mid, index] : material_of_mid) {
    index = static_cast<int>(mesh.material_names.size());
    mesh.material_names.push_back(material_name(deck, mid));
  }
  std::vector<Eigen::Vector3i> tris;
  std::vector<int> tri_node, tri_material, tri_back;
  auto material_index = [&](const std::string& name) {
    const auto it = std::find(mesh.material_names.begin(), mesh.material_names.end(), name);
    if (it != mesh.material_names.end()) return static_cast<int>(it - mesh.material_names.begin());
    mesh.material_names.push_back(name);
    return static_cast<int>(mesh.material_names.size()) - 1;
  };
  for (const Element& e : elements) {
    int v[4];
    for (std::size_t k = 0; k < e.grids.size(); ++k) {
      const auto it = vertex_of_grid.find(e.grids[k]);
      if (it == vertex_of_grid.end())
        throw line_error(file, e.card->line, printable(e.card->name, 16) + " " + printable(e.card->fields[0], 16) + ": GRID " + std::to_string(e.grids[k]) +
                                                 " is not defined in the file");
      v[k] = it->second;
    }
    const auto pm = material_of_property.find(e.pid);
    const int material = pm != material_of_property.end() && pm->second > 0 ? material_of_mid.at(pm->second) : -1;
    const auto back = deck.back_materials.find(e.eid);
    const int back_material = back != deck.back_materials.end() ? material_index(back->second) : -1;
    // A quad is split along its 1-3 diagonal; both triangles keep its corner order.
    for (int t = 0; t + 2 < static_cast<int>(e.grids.size()); ++t) {
      tris.emplace_back(v[0], v[t + 1], v[t + 2]);
      tri_node.push_back(node_of_pid.at(e.pid));
      tri_material.push_back(material);
      tri_back.push_back(back_material);
    }
  }
  const int nf = static_cast<int>(tris.size());
  mesh.F.resize(nf, 3);
  mesh.face_node.resize(nf);
  mesh.face_material.resize(nf);
  mesh.face_back_material.resize(nf);
  for (int i = 0; i < nf; ++i) {
    mesh.F.row(i) = tris[i].transpose();
    mesh.face_node[i] = tri_node[i];
    mesh.face_material[i] = tri_material[i];
    mesh.face_back_material[i] = tri_back[i];
  }
  return mesh;
}

}  // namespace mesh_formats

bool is_nastran_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".bdf" || ext == ".nas" || ext == ".dat";
}

std::vector<BdfRadiationProperties> read_bdf_radiation_properties(const std::filesystem::path& path) {
  using namespace mesh_formats;
  const std::string file = path.string();
  const Deck deck = load_deck(path);
  std::vector<BdfRadiationProperties> out;
  for (const Card& c : deck.cards) {
    if (c.name != "RADM") continue;
    const Fields f(c, file);
    const long long id = f.integer(2, "RADMID");
    const double alpha = f.real(3, "ABSORP"), eps = f.real(4, "EMIS1");
    if (!(alpha > 0.0 && alpha <= 1.0)) f.fail(3, "ABSORP", "must be in (0, 1]");
    if (!(eps > 0.0 && eps <= 1.0)) f.fail(4, "EMIS1", "must be in (0, 1]");
    out.push_back({material_name(deck, id), alpha, eps});
  }
  return out;
}

}  // namespace thermodec
