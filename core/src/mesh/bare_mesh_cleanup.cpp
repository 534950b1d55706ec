// Cleanup of bare CAD meshes. The measured reason for each step is in docs/benchmarks.md
// ("Reduction: NASA meshes"): on NPP_16, 67 of 86 parts are open sheets exported one-sided (solar array
// and panels as single quads) and touching parts leave faces facing each other at zero
// distance; both make the Monte Carlo couplings non-reciprocal and the noise floor large.
#include "thermodec/mesh/bare_mesh_cleanup.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/mesh/enclosing_shells.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/mesh/overlapping_sheets.h"
#include "thermodec/mesh/remove_faces.h"
#include "thermodec/mesh/repair.h"

namespace thermodec {
namespace {

int attr(const Eigen::VectorXi& a, int f) { return a.size() > f ? a[f] : -1; }

// Keeps the faces with keep[f] != 0; provenance and two-sided flags follow.
void keep_faces(Mesh& m, Eigen::VectorXi& source, Eigen::VectorXi& two_sided, const std::vector<char>& keep,
                Eigen::VectorXi* tag = nullptr) {
  const std::vector<int> kept = remove_faces(m, keep);
  source = source(kept).eval();
  two_sided = two_sided(kept).eval();
  if (tag && tag->size()) *tag = (*tag)(kept).eval();
}

void make_two_sided(Mesh& m, Eigen::VectorXi& two_sided, int f, int back_material) {
  two_sided[f] = 1;
  if (m.face_back_material[f] < 0) m.face_back_material[f] = back_material;
}

// Step 2: faces on the same three vertices. An opposite-orientation pair is either a sheet
// exported as two back-to-back faces or the contact of two touching solids whose vertices were
// welded; the surroundings tell them apart: without the pairs, a contact's rim still closes
// (every rim edge keeps >= 2 other faces), a sheet's does not.
void merge_index_duplicates(Mesh& m, Eigen::VectorXi& source, Eigen::VectorXi& two_sided, BareMeshCleanupReport& rep) {
  const int nf = m.num_faces();
  std::vector<std::pair<std::array<int, 3>, int>> sorted(nf);
  for (int f = 0; f < nf; ++f) {
    std::array<int, 3> t{m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    std::sort(t.begin(), t.end());
    sorted[f] = {t, f};
  }
  std::sort(sorted.begin(), sorted.end());
  // Orientation parity: a face is an even or odd permutation of its sorted corners.
  auto parity = [&](int f) {
    const int a = m.F(f, 0), b = m.F(f, 1), c = m.F(f, 2);
    return (a < b) + (b < c) + (c < a) == 2;
  };
  std::vector<char> keep(nf, 1);
  std::vector<std::pair<int, int>> pairs;  // (survivor, its reversed twin)
  for (int i = 0; i < nf;) {
    int j = i;
    while (j < nf && sorted[j].first == sorted[i].first) ++j;
    const int first = sorted[i].second;
    int twin = -1;
    for (int k = i + 1; k < j; ++k) {
      const int g = sorted[k].second;
      keep[g] = 0;
      if (twin < 0 && parity(g) != parity(first) && !two_sided[first] && m.face_back_material[first] < 0)
        twin = g;
      else
        ++rep.duplicate_faces_dropped;
    }
    if (twin >= 0) pairs.emplace_back(first, twin);
    i = j;
  }
  if (!pairs.empty()) {
    std::vector<char> in_pair(nf, 0);
    for (const auto& [a, b] : pairs) in_pair[a] = in_pair[b] = 1;
    std::map<std::pair<int, int>, int> other_faces, pair_faces;  // per edge: faces outside pairs / pair survivors
    auto edge = [&](int f, int k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      return std::make_pair(std::min(a, b), std::max(a, b));
    };
    for (int f = 0; f < nf; ++f)
      if (keep[f] && !in_pair[f])
        for (int k = 0; k < 3; ++k) ++other_faces[edge(f, k)];
    for (const auto& pr : pairs)
      for (int k = 0; k < 3; ++k) ++pair_faces[edge(pr.first, k)];
    const Eigen::VectorXd area = face_areas(m.V, m.F);
    for (const auto& [a, b] : pairs) {
      bool contact = true;
      for (int k = 0; k < 3 && contact; ++k) {
        const auto e = edge(a, k);
        const auto it = other_faces.find(e);
        const int others = it == other_faces.end() ? 0 : it->second;
        contact = others >= 2 || (others == 0 && pair_faces[e] >= 2);
      }
      if (contact) {
        keep[a] = 0;
        rep.coincident_faces_dropped += 2;
        rep.coincident_area_dropped_m2 += 2 * area[a];
      } else {
        make_two_sided(m, two_sided, a, attr(m.face_material, b));
        ++rep.back_to_back_pairs_merged;
      }
    }
  }
  if (std::find(keep.begin(), keep.end(), 0) != keep.end()) keep_faces(m, source, two_sided, keep);
}

// Step 3: components with open edges radiate from both sides.
void two_sided_open_sheets(Mesh& m, Eigen::VectorXi& two_sided, BareMeshCleanupReport& rep) {
  const int nf = m.num_faces();
  if (nf == 0) return;
  Eigen::VectorXi comp;
  const std::vector<char> closed = closed_components(m.F, comp);
  for (char c : closed) (c ? rep.closed_components : rep.open_components)++;
  for (int f = 0; f < nf; ++f) {
    if (closed[comp[f]] || two_sided[f] || m.face_back_material[f] >= 0) continue;
    make_two_sided(m, two_sided, f, m.face_material[f]);
    ++rep.open_sheet_faces_made_two_sided;
  }
}

// Step 5, found before step 4 (whose dropped contact faces would open the touching parts):
// #F 1 = face of a closed part with other faces inside it.
Eigen::VectorXi find_enclosing_shells(const Mesh& m, double on_surface_m, BareMeshCleanupReport& rep) {
  Eigen::VectorXi comp;
  const std::vector<char> closed = closed_components(m.F, comp);
  const EnclosingShells e = enclosing_shells(m, comp, closed, on_surface_m);
  Eigen::VectorXi shell(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) {
    shell[f] = e.shell_face[f];
    rep.enclosed_faces += e.enclosed_face[f];
  }
  rep.enclosing_shells = e.shells;
  return shell;
}

// Step 4: one-sided faces lying on an opposite-facing face (touching parts). Sweep over the
// faces' boxes along x; candidates are tested at 7 interior sample points, and a face goes when
// most of them (4 of 7) lie on an opposite face.
void drop_coincident_faces(Mesh& m, Eigen::VectorXi& source, Eigen::VectorXi& two_sided, Eigen::VectorXi& shell,
                           double distance, BareMeshCleanupReport& rep) {
  const int nf = m.num_faces();
  const Eigen::MatrixXd N = face_normals(m.V, m.F);
  const Eigen::VectorXd A = face_areas(m.V, m.F);
  std::vector<Eigen::AlignedBox3d> box(nf);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) box[f].extend(Eigen::Vector3d(m.V.row(m.F(f, k)).transpose()));
  std::vector<int> order(nf);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::make_pair(box[a].min().x(), a) < std::make_pair(box[b].min().x(), b);
  });
  static constexpr double kBary[7][3] = {{1. / 3, 1. / 3, 1. / 3}, {.6, .2, .2},  {.2, .6, .2}, {.2, .2, .6},
                                         {.45, .45, .1},         {.1, .45, .45}, {.45, .1, .45}};
  auto corner = [&](int f, int k) -> Eigen::Vector3d { return m.V.row(m.F(f, k)).transpose(); };
  std::vector<char> keep(nf, 1);
  std::vector<std::array<char, 7>> covered(nf);
  for (auto& c : covered) c.fill(0);
  for (int i = 0; i < nf; ++i) {
    const int f = order[i];
    if (!(A[f] > 0) || two_sided[f]) continue;
    for (int j = i + 1; j < nf && box[order[j]].min().x() <= box[f].max().x() + distance; ++j) {
      const int g = order[j];
      if (!(A[g] > 0) || two_sided[g]) continue;
      if (N.row(f).dot(N.row(g)) > -(1 - 1e-4)) continue;
      Eigen::AlignedBox3d bf = box[f];
      bf.min().array() -= distance;
      bf.max().array() += distance;
      if (!bf.intersects(box[g])) continue;
      // Symmetric test: f's samples on g and g's samples on f.
      for (const auto& [p, q] : {std::make_pair(f, g), std::make_pair(g, f)}) {
        const Eigen::Vector3d nq = N.row(q).transpose(), a = corner(q, 0), b = corner(q, 1), c = corner(q, 2);
        for (int s = 0; s < 7; ++s) {
          if (covered[p][s]) continue;
          const Eigen::Vector3d x = kBary[s][0] * corner(p, 0) + kBary[s][1] * corner(p, 1) + kBary[s][2] * corner(p, 2);
          const double h = (x - a).dot(nq);
          if (std::abs(h) > distance) continue;
          const Eigen::Vector3d y = x - h * nq;
          auto inside = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& v) { return (v - u).cross(y - u).dot(nq) >= 0; };
          if (inside(a, b) && inside(b, c) && inside(c, a)) covered[p][s] = 1;
        }
      }
    }
  }
  for (int f = 0; f < nf; ++f) {
    int n = 0;
    for (char c : covered[f]) n += c;
    if (n >= 4) {
      keep[f] = 0;
      ++rep.coincident_faces_dropped;
      rep.coincident_area_dropped_m2 += A[f];
    }
  }
  if (rep.coincident_faces_dropped) keep_faces(m, source, two_sided, keep, &shell);
}

// Composes provenance: out[i] = first[second[i]].
Eigen::VectorXi compose(const Eigen::VectorXi& first, const Eigen::VectorXi& second) {
  Eigen::VectorXi out(second.size());
  for (int i = 0; i < second.size(); ++i) out[i] = first[second[i]];
  return out;
}

}  // namespace

bool BareMeshCleanupReport::changed() const {
  return vertices_welded || degenerate_faces_dropped || t_junctions_split || faces_flipped || duplicate_faces_dropped ||
         back_to_back_pairs_merged || open_sheet_faces_made_two_sided || coincident_faces_dropped ||
         shell_faces_made_two_sided || overlapping_sheet_faces_dropped;
}

std::string BareMeshCleanupReport::summary() const {
  std::ostringstream s;
  auto line = [&s](int n, const char* what) {
    if (n) s << what << ": " << n << "\n";
  };
  s << "faces: " << faces_in << " -> " << faces_out << "\n";
  line(vertices_welded, "vertices welded");
  line(degenerate_faces_dropped, "degenerate faces dropped");
  line(t_junctions_split, "T-junction edge bisections");
  line(faces_flipped, "faces flipped (consistent orientation, closed parts outward)");
  line(duplicate_faces_dropped, "duplicate faces dropped");
  line(back_to_back_pairs_merged, "back-to-back face pairs merged into two-sided faces");
  s << "parts: " << closed_components << " closed (one-sided), " << open_components << " open sheets\n";
  line(open_sheet_faces_made_two_sided, "open-sheet faces made two-sided");
  if (coincident_faces_dropped)
    s << "coincident faces of touching parts dropped: " << coincident_faces_dropped << " (" << coincident_area_dropped_m2
      << " m^2)\n";
  if (overlapping_sheet_faces_dropped)
    s << "two-sided faces lying on a larger sheet dropped: " << overlapping_sheet_faces_dropped << " ("
      << overlapping_sheet_area_dropped_m2 << " m^2)\n";
  if (enclosing_shells)
    s << "closed parts with faces inside, made two-sided: " << enclosing_shells << " (" << shell_faces_made_two_sided
      << " faces; " << enclosed_faces << " faces inside)\n";
  return s.str();
}

BareMeshCleanupResult cleanup_bare_mesh(const Mesh& mesh, const BareMeshCleanupOptions& o) {
  if (!(o.relative_tolerance >= 0) || !(o.coincident_relative_distance >= 0))
    throw InvalidInput("mesh cleanup: tolerances must be >= 0");
  BareMeshCleanupResult res;
  BareMeshCleanupReport& rep = res.report;
  const int nf = mesh.num_faces();
  rep.faces_in = nf;
  Mesh m = mesh;
  if (m.face_node.size() != nf) m.face_node = Eigen::VectorXi::Constant(nf, -1);
  if (m.face_material.size() != nf) m.face_material = Eigen::VectorXi::Constant(nf, -1);
  if (m.face_back_material.size() != nf) m.face_back_material = Eigen::VectorXi::Constant(nf, -1);
  Eigen::VectorXi source = Eigen::VectorXi::LinSpaced(nf, 0, nf - 1);
  if (o.repair) {
    // Orientation waits until back-to-back pairs are merged: a pair shares all three edges and
    // would otherwise steer the orientation of its neighbours.
    RepairOptions ro;
    ro.relative_tolerance = o.relative_tolerance;
    ro.drop_duplicates = false;
    ro.orient = false;
    RepairResult r = repair_mesh(m, ro);
    m = std::move(r.mesh);
    source = r.source_face;
    rep.vertices_welded = r.report.vertices_welded;
    rep.degenerate_faces_dropped = r.report.degenerate_faces_dropped;
    rep.t_junctions_split = r.report.t_junctions_split;
  } else {
    for (int v = 0; v < m.num_vertices(); ++v)
      if (!m.V.row(v).allFinite()) throw InvalidInput("mesh cleanup: vertex " + std::to_string(v) + " is not finite");
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        if (m.F(f, k) < 0 || m.F(f, k) >= m.num_vertices())
          throw InvalidInput("mesh cleanup: face " + std::to_string(f) + " has a vertex index out of range");
  }
  res.two_sided = Eigen::VectorXi::Zero(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) res.two_sided[f] = m.face_back_material[f] >= 0;
  if (o.merge_duplicate_faces) merge_index_duplicates(m, source, res.two_sided, rep);
  if (o.repair) {
    RepairOptions ro;
    ro.weld = ro.drop_degenerate = ro.drop_duplicates = ro.conform_t_junctions = false;
    RepairResult r = repair_mesh(m, ro);
    rep.faces_flipped = r.report.faces_flipped;
    res.two_sided = compose(res.two_sided, r.source_face);
    source = compose(source, r.source_face);
    m = std::move(r.mesh);
  }
  if (o.two_sided_open_sheets) two_sided_open_sheets(m, res.two_sided, rep);
  const double diag = m.num_faces() ? (m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).norm() : 0.0;
  Eigen::VectorXi shell;
  if (o.two_sided_enclosing_shells) shell = find_enclosing_shells(m, o.coincident_relative_distance * diag, rep);
  if (o.drop_coincident_faces && m.num_faces() > 0)
    drop_coincident_faces(m, source, res.two_sided, shell, o.coincident_relative_distance * diag, rep);
  if (o.drop_coincident_faces && m.num_faces() > 0) {  // step 6
    const std::vector<char> keep = overlapping_sheet_faces(m, res.two_sided, o.coincident_relative_distance * diag);
    const Eigen::VectorXd area = face_areas(m.V, m.F);
    for (int f = 0; f < m.num_faces(); ++f)
      if (!keep[f]) ++rep.overlapping_sheet_faces_dropped, rep.overlapping_sheet_area_dropped_m2 += area[f];
    if (std::find(keep.begin(), keep.end(), 0) != keep.end()) keep_faces(m, source, res.two_sided, keep, &shell);
  }
  for (int f = 0; f < shell.size(); ++f) {
    if (!shell[f] || res.two_sided[f] || m.face_back_material[f] >= 0) continue;
    make_two_sided(m, res.two_sided, f, m.face_material[f]);
    ++rep.shell_faces_made_two_sided;
  }
  rep.faces_out = m.num_faces();
  res.mesh = std::move(m);
  res.source_face = source;
  return res;
}

}  // namespace thermodec
