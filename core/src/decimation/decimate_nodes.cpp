// Node-preserving decimation on vcglib's local optimisation framework: the driver. It checks
// the input, sets the constraints (mesh_regions.cpp) and the per-node face budgets, runs the
// collapses (node_collapse.h: cost, vertex placement, constraints) and assembles the coarse mesh
// with its provenance and per-node report.
//
// References:
//  P. Lindstrom, G. Turk, "Fast and memory efficient polygonal simplification", IEEE Vis 1998
//    (volume preservation / volume optimisation / boundary / shape objectives, solved as a
//    hierarchy of linear constraints with the "alpha compatibility" test).
//  T. Dey, H. Edelsbrunner et al., "Topology preserving edge contraction", 1999 (link condition).
//
// Why our own collapse type instead of vcg's quadric one: the quadric metric does not preserve
// volume or node areas and treats node interfaces like any edge, so it opens cracks between
// nodes; here regions (node, material, back material) are hard constraints.
#include "thermodec/decimation/decimate_nodes.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "contact_release.h"
#include "near_contacts.h"
#include "node_collapse.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/global_ratio.h"

namespace thermodec {
namespace {

using namespace collapse;

void check_input(const Mesh& mesh) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (mesh.V.cols() != 3 && nv > 0) throw InvalidInput("decimate: V must be #V x 3");
  if (mesh.F.cols() != 3 && nf > 0) throw InvalidInput("decimate: F must be #F x 3");
  if (mesh.face_node.size() != nf)
    throw InvalidInput("decimate: face_node has " + std::to_string(mesh.face_node.size()) +
                       " entries for " + std::to_string(nf) + " faces");
  for (int f = 0; f < nf; ++f) {
    for (int j = 0; j < 3; ++j)
      if (mesh.F(f, j) < 0 || mesh.F(f, j) >= nv)
        throw InvalidInput("decimate: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(mesh.F(f, j)) + " outside [0, " + std::to_string(nv) + ")");
    if (mesh.face_node[f] < -1)
      throw InvalidInput("decimate: face " + std::to_string(f) + " has node " +
                         std::to_string(mesh.face_node[f]));
  }
  if (!mesh.V.allFinite()) throw InvalidInput("decimate: vertex coordinates contain NaN or inf");
}

// DecimationOptions::reflection: consistent sizes, finite values >= 0, views of real nodes.
void check_reflection_data(const DecimationOptions::ReflectionData& r, int nf, int num_nodes) {
  if (r.empty()) return;
  const size_t sides = 2 * static_cast<size_t>(nf);
  if (r.flux_W_per_m2.size() != sides || r.view_start.size() != sides + 1 || r.view_start.front() != 0 ||
      r.view_node.size() != r.view_fraction.size() || static_cast<size_t>(r.view_start.back()) != r.view_node.size() ||
      r.node_absorbed_W.size() != static_cast<size_t>(num_nodes))
    throw InvalidInput("decimate: reflection data must have 2 fluxes and 2 view lists per face (" +
                       std::to_string(nf) + " faces) and an absorbed power per node");
  for (size_t s = 0; s < sides; ++s)
    if (r.view_start[s + 1] < r.view_start[s]) throw InvalidInput("decimate: reflection view_start must not decrease");
  auto bad = [](double x) { return !(x >= 0 && std::isfinite(x)); };
  for (double q : r.flux_W_per_m2)
    if (bad(q)) throw InvalidInput("decimate: reflected fluxes must be finite and >= 0");
  for (double q : r.view_fraction)
    if (bad(q)) throw InvalidInput("decimate: reflection view fractions must be finite and >= 0");
  for (double q : r.node_absorbed_W)
    if (bad(q)) throw InvalidInput("decimate: node absorbed powers must be finite and >= 0");
  for (int g : r.view_node)
    if (g < 0 || g >= num_nodes) throw InvalidInput("decimate: a reflection view names node " + std::to_string(g));
}

// Node face counts, targets and areas [m^2]; returns the total target face count.
int set_node_budgets(const Mesh& mesh, const NodeGroups& group_of, int groups, int num_nodes,
                     const Eigen::VectorXd& target_ratio_per_node, const DecimationOptions& options, Context& c) {
  const int nf = mesh.num_faces();
  c.node_faces.assign(groups, 0);
  c.node_area0.assign(groups, 0.0);
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = mesh.V.row(mesh.F(f, 0)), p1 = mesh.V.row(mesh.F(f, 1)), p2 = mesh.V.row(mesh.F(f, 2));
    ++c.node_faces[group_of(f)];
    c.node_area0[group_of(f)] += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  c.node_area = c.node_area0;
  c.node_area_bound.assign(groups, options.max_relative_area_change);
  for (int g = 0; g < num_nodes && g < static_cast<int>(options.node_max_relative_area_change.size()); ++g)
    c.node_area_bound[g] = options.node_max_relative_area_change[g];
  c.node_sharp.assign(groups, 0.0);
  c.node_free_removed.assign(groups, 0);
  c.node_target.resize(groups);
  int total_target = 0;
  for (int g = 0; g < groups; ++g) {
    const double ratio = g < num_nodes ? target_ratio_per_node[g] : options.unassigned_ratio;
    const int keep = static_cast<int>(std::lround(c.node_faces[g] * (1.0 - ratio)));
    c.node_target[g] = std::min(c.node_faces[g], std::max(keep, options.min_faces_per_node));
    total_target += c.node_target[g];
  }
  return total_target;
}

// The coarse mesh left in `m`, with its provenance and per-node and per-part report.
DecimationResult assemble_result(const Mesh& mesh, VMesh& m, const Context& c, int collapses, int groups,
                                 const NodeGroups& group_of, int ncomp) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  DecimationResult res;
  res.collapses = collapses;
  std::vector<int> new_vertex(nv, -1);
  std::vector<int> kept_faces;
  for (int f = 0; f < nf; ++f)
    if (!m.face[f].IsD()) kept_faces.push_back(f);
  for (int f : kept_faces)
    for (int j = 0; j < 3; ++j) new_vertex[c.vi(m.face[f].V(j))] = 1;
  int nv_out = 0;  // surviving vertices keep their input order
  for (int& nvx : new_vertex) nvx = nvx > 0 ? nv_out++ : -1;
  Mesh& out = res.mesh;
  out.V.resize(nv_out, 3);
  res.fine_vertex_of_coarse.resize(nv_out);
  for (int v = 0; v < nv; ++v)
    if (new_vertex[v] >= 0) {
      for (int k = 0; k < 3; ++k) out.V(new_vertex[v], k) = m.vert[v].cP()[k];
      res.fine_vertex_of_coarse[new_vertex[v]] = v;
    }
  const int nf_out = static_cast<int>(kept_faces.size());
  out.F.resize(nf_out, 3);
  out.face_node.resize(nf_out);
  out.face_material.resize(nf_out);
  out.face_back_material.resize(nf_out);
  res.fine_face_of_coarse.resize(nf_out);
  std::vector<int> coarse_of(nf, -1);
  for (int i = 0; i < nf_out; ++i) {
    const int f = kept_faces[i];
    for (int j = 0; j < 3; ++j) out.F(i, j) = new_vertex[c.vi(m.face[f].V(j))];
    out.face_node[i] = mesh.face_node[f];
    out.face_material[i] = attr(mesh.face_material, f);
    out.face_back_material[i] = attr(mesh.face_back_material, f);
    res.fine_face_of_coarse[i] = f;
    coarse_of[f] = i;
  }
  out.node_names = mesh.node_names;
  out.material_names = mesh.material_names;
  res.coarse_face_of_fine.resize(nf);
  for (int f = 0; f < nf; ++f) {
    int g = f;
    while (coarse_of[g] < 0 && c.absorbed_by[g] >= 0) g = c.absorbed_by[g];
    res.coarse_face_of_fine[f] = coarse_of[g];
  }

  res.nodes.resize(groups);
  for (int g = 0; g < groups; ++g) {
    res.nodes[g].area_before_m2 = c.node_area0[g];
    res.nodes[g].target_faces = c.node_target[g];
    res.nodes[g].faces_removed_free = c.node_free_removed[g];
  }
  for (int f = 0; f < nf; ++f) ++res.nodes[group_of(f)].faces_before;
  for (int i = 0; i < nf_out; ++i) {
    const int f = kept_faces[i];
    const Vec3 p0 = out.V.row(out.F(i, 0)), p1 = out.V.row(out.F(i, 1)), p2 = out.V.row(out.F(i, 2));
    auto& s = res.nodes[group_of(f)];
    ++s.faces_after;
    s.area_after_m2 += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  for (auto& s : res.nodes) s.reached = s.faces_after <= s.target_faces;
  std::vector<double> volume_after(ncomp, 0.0);
  for (int i = 0; i < nf_out; ++i) {
    const Vec3 p0 = out.V.row(out.F(i, 0)), p1 = out.V.row(out.F(i, 1)), p2 = out.V.row(out.F(i, 2));
    volume_after[c.face_component[kept_faces[i]]] += p0.dot(p1.cross(p2)) / 6.0;
  }
  for (int k = 0; k < ncomp; ++k)
    if (c.comp_closed[k]) {
      res.closed_volume_before_m3.push_back(c.comp_volume0[k]);
      res.closed_volume_after_m3.push_back(volume_after[k]);
    }
  return res;
}

// Maps the coarse vertices of a decimation run on released contacts (contact_release.h) back
// to input vertices: a copy left unmoved where its input vertex also survives is the same
// point, so the faces get that vertex back (where nothing coarsened the contact, the output
// is as conforming as the input).
void rejoin_contacts(const ContactRelease& rel, DecimationResult& res) {
  Mesh& out = res.mesh;
  const int n = out.num_vertices();
  std::vector<int> output_of_input(rel.input_vertex.size(), -1);
  for (int i = 0; i < n; ++i) output_of_input[res.fine_vertex_of_coarse[i]] = i;
  std::vector<int> same(n);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    const int w = res.fine_vertex_of_coarse[i], v = rel.input_vertex[w];
    const int o = v != w ? output_of_input[v] : -1;
    same[i] = o >= 0 && out.V.row(o) == out.V.row(i) ? o : i;
    kept += same[i] == i;
  }
  std::vector<int> index(n, -1);
  Eigen::MatrixXd V(kept, 3);
  Eigen::VectorXi fine(kept);
  for (int i = 0, k = 0; i < n; ++i)
    if (same[i] == i) {
      index[i] = k;
      V.row(k) = out.V.row(i);
      fine[k++] = rel.input_vertex[res.fine_vertex_of_coarse[i]];
    }
  for (int f = 0; f < out.num_faces(); ++f)
    for (int j = 0; j < 3; ++j) out.F(f, j) = index[same[out.F(f, j)]];
  out.V = std::move(V);
  res.fine_vertex_of_coarse = std::move(fine);
}

}  // namespace

DecimationResult decimate_nodes(const Mesh& mesh, const Eigen::VectorXd& target_ratio_per_node,
                                const DecimationOptions& options) {
  check_input(mesh);
  const int nf = mesh.num_faces();
  int num_nodes = static_cast<int>(mesh.node_names.size());
  bool has_unassigned = false;
  for (int f = 0; f < nf; ++f) {
    num_nodes = std::max(num_nodes, mesh.face_node[f] + 1);
    has_unassigned |= mesh.face_node[f] < 0;
  }
  if (target_ratio_per_node.size() < num_nodes)
    throw InvalidInput("decimate: " + std::to_string(target_ratio_per_node.size()) +
                       " node ratios for " + std::to_string(num_nodes) + " nodes");
  for (int i = 0; i < target_ratio_per_node.size(); ++i)
    if (!(target_ratio_per_node[i] >= 0 && target_ratio_per_node[i] <= 1))
      throw InvalidInput("decimate: ratio of node " + std::to_string(i) + " is " +
                         std::to_string(target_ratio_per_node[i]) + ", expected in [0, 1]");
  if (!(options.unassigned_ratio >= 0 && options.unassigned_ratio <= 1))
    throw InvalidInput("decimate: unassigned_ratio must be in [0, 1]");
  if (!(options.max_relative_area_change >= 0) || !(options.max_relative_volume_change >= 0) ||
      !(options.max_contour_deviation >= 0) || !(options.exact_contour_tolerance >= 0) ||
      !(options.radiative_cost_weight >= 0) || !(options.projected_area_budget >= 0) ||
      !(options.max_kinked_contour_deviation >= 0) || !(options.wide_kink_area_fraction >= 0) ||
      !(options.wide_kink_part_fraction >= 0) ||
      !(options.projected_area_cap >= 0) ||
      !(options.max_restoring_offset > 0) ||
      options.min_faces_per_node < 1 || options.passes < 1)
    throw InvalidInput("decimate: tolerances must be >= 0, min_faces_per_node and passes >= 1");
  const auto& node_bounds = options.node_max_relative_area_change;
  if (!node_bounds.empty() && static_cast<int>(node_bounds.size()) < num_nodes)
    throw InvalidInput("decimate: " + std::to_string(node_bounds.size()) + " per-node area bounds for " +
                       std::to_string(num_nodes) + " nodes");
  for (double b : node_bounds)
    if (!(b >= 0 && std::isfinite(b))) throw InvalidInput("decimate: per-node area bounds must be finite and >= 0");
  if (!(options.max_fold_deg > 0 && options.max_fold_deg <= 179))
    throw InvalidInput("decimate: max_fold_deg must be in (0, 179]");
  check_reflection_data(options.reflection, mesh.num_faces(), num_nodes);
  if (!(options.reflection_cap >= 0)) throw InvalidInput("decimate: reflection_cap must be >= 0");
  if (!(options.near_contact_fraction >= 0 && std::isfinite(options.near_contact_fraction)))
    throw InvalidInput("decimate: near_contact_fraction must be finite and >= 0");

  const int groups = num_nodes + (has_unassigned ? 1 : 0);
  const NodeGroups group_of{mesh, num_nodes};

  Context c;
  c.opt = options;
  c.cos_normal = std::cos(options.max_normal_deviation_deg * M_PI / 180.0);
  c.cos_fold = std::cos(std::max(options.max_fold_deg, options.max_normal_deviation_deg) * M_PI / 180.0);

  // With release_contacts the collapses run on a copy whose contact vertices are split
  // (contact_release.h); faces keep their indices, so group_of and the budgets are unchanged.
  ContactRelease rel;
  if (options.release_contacts) {
    Context regions;
    classify_mesh(mesh, group_of, regions);
    rel = release_contacts(mesh, regions.face_region, options.exact_contour_tolerance);
    c.contact_frozen = rel.keep_frozen;
  }
  const Mesh& work = rel.released > 0 ? rel.mesh : mesh;
  const int nv = work.num_vertices();
  if (options.near_contact_fraction > 0) {  // found on the input, frozen on every copy of the vertex
    const std::vector<char> near = near_contact_vertices(mesh, options.near_contact_fraction);
    c.contact_frozen.resize(static_cast<size_t>(nv), 0);
    for (int v = 0; v < nv; ++v) {
      const int in = rel.released > 0 ? rel.input_vertex[static_cast<size_t>(v)] : v;
      c.contact_frozen[static_cast<size_t>(v)] |= near[static_cast<size_t>(in)];
    }
  }
  const int ncomp = classify_mesh(work, group_of, c);
  const int total_target = set_node_budgets(work, group_of, groups, num_nodes, target_ratio_per_node, options, c);

  // Scale: priorities are floats in vcg's heap, so make the cost dimensionless.
  double diag = 1.0;
  if (nv > 0) diag = (work.V.colwise().maxCoeff() - work.V.colwise().minCoeff()).norm();
  if (!(diag > 0)) diag = 1.0;
  c.cost_scale = 1.0 / std::pow(diag, 6);
  c.degenerate_area2 = std::pow(1e-12 * diag * diag, 2);

  // Build the vcg mesh; vertex/face indices equal the input ones (vcg only flags deletions).
  VMesh m;
  c.m = &m;
  vcg::tri::Allocator<VMesh>::AddVertices(m, nv);
  vcg::tri::Allocator<VMesh>::AddFaces(m, nf);
  for (int v = 0; v < nv; ++v) m.vert[v].P() = vcg::Point3d(work.V(v, 0), work.V(v, 1), work.V(v, 2));
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) m.face[f].V(j) = &m.vert[work.F(f, j)];
  vcg::tri::UpdateTopology<VMesh>::VertexFace(m);
  c.absorbed_by.assign(nf, -1);
  c.stamp.assign(nv, 0);
  if (options.projected_area_cap > 0) c.node_projection_change.assign(groups, Context::Projection{});
  if (!options.reflection.empty()) {
    // Reflected-sunlight cap (reflection_cap.cpp): each face side's flux and views.
    const auto& r = options.reflection;
    c.face_flux.resize(nf);
    c.face_view.resize(nf);
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 2; ++k) {
        const int s = 2 * f + k;
        c.face_flux[f][k] = r.flux_W_per_m2[s];
        for (int e = r.view_start[s]; e < r.view_start[s + 1]; ++e)
          c.face_view[f][k].emplace_back(r.view_node[e], r.view_fraction[e]);
      }
    c.node_reflection_change_W.assign(static_cast<size_t>(groups) * num_nodes, 0.0);
    c.reflection_scratch.assign(num_nodes, 0.0);
  }
  if (options.projected_area_cap > 0 && options.restore_node_areas) {
    c.group_faces.assign(groups, {});
    for (int f = 0; f < nf; ++f) c.group_faces[group_of(f)].push_back(f);
    c.restore_slot.assign(nv, -1);
  }

  int collapses = 0;
  bool needs_work = false;
  for (int g = 0; g < groups; ++g) needs_work |= c.node_target[g] < c.node_faces[g];
  if (needs_work && nf > 0) {
    vcg::LocalOptimization<VMesh> opt(m, &c);
    c.heap = &opt.h;
    opt.Init<NodeCollapse>();
    opt.SetTargetSimplices(total_target);
    c.target_simplices = &opt.nTargetSimplices;
    opt.DoOptimization();
    collapses = opt.nPerformedOps;
    // note: a collapse refused when it comes off the heap (a neighbour's budget, an area that
    // has since drifted back) is queued again only when its star changes. With passes > 1,
    // once the heap is empty every remaining edge is queued once more, while that still
    // collapses something (DecimationOptions::passes).
    for (int pass = 1; pass < options.passes && opt.nPerformedOps > 0 && m.fn > opt.nTargetSimplices; ++pass) {
      opt.Init<NodeCollapse>();
      opt.DoOptimization();
      collapses += opt.nPerformedOps;
    }
  }

  const auto blocked = collapse::explain_reach(m, c);
  DecimationResult res = assemble_result(work, m, c, collapses, groups, group_of, ncomp);
  if (rel.released > 0) rejoin_contacts(rel, res);
  for (int g = 0; g < groups; ++g)
    if (!res.nodes[g].reached) res.nodes[g].blocked_edges = blocked[g];
  return res;
}

DecimationResult decimate_to_global_ratio(const Mesh& mesh, double global_ratio,
                                          const DecimationOptions& options, int max_rounds) {
  if (!(global_ratio >= 0 && global_ratio < 1))
    throw InvalidInput("decimate: global ratio " + std::to_string(global_ratio) + " not in [0, 1)");
  int num_nodes = static_cast<int>(mesh.node_names.size());
  bool has_unassigned = false;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    num_nodes = std::max(num_nodes, mesh.face_node[f] + 1);
    has_unassigned |= mesh.face_node[f] < 0;
  }
  const int groups = num_nodes + (has_unassigned ? 1 : 0);
  Eigen::VectorXi counts = Eigen::VectorXi::Zero(groups);
  for (int f = 0; f < mesh.num_faces(); ++f)
    ++counts[mesh.face_node[f] >= 0 ? mesh.face_node[f] : num_nodes];
  Eigen::VectorXd cap = Eigen::VectorXd::Ones(groups);
  Eigen::VectorXd ratios = node_ratios_for_global_ratio(counts, global_ratio, options.min_faces_per_node, cap);
  DecimationResult res;
  for (int round = 0; round < std::max(1, max_rounds); ++round) {
    DecimationOptions o = options;
    if (has_unassigned) o.unassigned_ratio = ratios[num_nodes];
    res = decimate_nodes(mesh, ratios.head(num_nodes), o);
    // A node stopped short by the constraints caps its ratio at what it reached; the rule then
    // hands its deficit to the next nodes.
    // Each node stops within one collapse (<= 2 faces) of its rounded target, so a total within
    // `groups` faces of the global target is met; rerunning for that would only cost time.
    const int global_target = static_cast<int>(std::lround((1.0 - global_ratio) * mesh.num_faces()));
    if (res.mesh.num_faces() <= global_target + groups) break;
    bool short_of_target = false;
    for (int g = 0; g < groups; ++g)
      if (!res.nodes[g].reached && counts[g] > 0) {
        short_of_target = true;
        cap[g] = 1.0 - static_cast<double>(res.nodes[g].faces_after) / counts[g];
      }
    if (!short_of_target) break;
    const Eigen::VectorXd next = node_ratios_for_global_ratio(counts, global_ratio, options.min_faces_per_node, cap);
    if ((next - ratios).cwiseAbs().maxCoeff() < 1e-12) break;
    ratios = next;
  }
  return res;
}

}  // namespace thermodec
