// Reflected-sunlight cap (DecimationOptions::reflection, reflection_cap).
//
// A face reflects the sunlight (and albedo) it receives diffusely and uniformly over its area:
// the solar-band reflections (environment/solar_reflections.cpp) start from each side's mean
// incident power. Where a node is partly in a neighbour's shadow, the dark part is usually the
// part that sees that neighbour best (it is dark because the neighbour stands in front of it).
// Merging a lit face with a dark one keeps the node's area, projected area and absorbed power,
// but the merged face reflects the lit face's light from the dark face's place, onto the
// neighbour: measured on NPP_16, one flat plate taken from 5 to 3 faces reflects 31 % more
// sunlight into the unreduced node beside it (+273 W of 885 W), which alone moves that node by
// about +0.7 K. A coarse face covering several fine ones sees, to first order, what they saw on
// average; so a collapse gives the faces it changes (per node, per side) their area-weighted
// mean flux q_m [W/m^2] and mean views F_m,g, and the reflected power first reaching node g
// changes by sum_f A_f (q_m - q_f) F_fg = -sum_f A_f (q_f - q_m)(F_fg - F_m,g): minus the
// covariance of flux and view over the star, zero where either is uniform (inside a lit or a
// dark region, on a panel that sees nothing). One account per (source node, receiving node)
// sums these changes (signed: opposite changes cancel in what the receiver absorbs); a collapse
// that takes an account further from zero past reflection_cap x the receiver's area bound x its
// absorbed power is refused. Per source, so a node decimates the same way alone and with others
// (accounts shared by all sources broke the search's superposition on NPP_16).
#include <algorithm>
#include <cmath>

#include "node_collapse.h"

namespace thermodec::collapse {

// The changed faces of node `node` (into c.projection_faces) and what averaging them does to
// the reflected power reaching each node (into c.reflection_scratch, touched nodes listed in
// `touched`); their mean flux and views into `mean` / `mean_view`.
void NodeCollapse::reflection_change(Context& c, int node, std::array<double, 2>& mean,
                                     std::array<Context::View, 2>& mean_view, std::vector<int>& touched) const {
  gather_faces_around_moved_vertices(c);
  auto& faces = c.projection_faces;
  std::array<Vec3, 3> p, q;
  thread_local std::vector<double> areas;
  areas.clear();
  double area = 0;
  size_t changed = 0;
  for (VFace* f : faces) {
    if (c.region_node[c.face_region[c.fi(f)]] != node) continue;
    corners_before_after(f, p, q);
    if (p == q) continue;
    areas.push_back(0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm());
    area += areas.back();
    faces[changed++] = f;
  }
  faces.resize(changed);
  touched.clear();
  mean = {0.0, 0.0};
  mean_view = {};
  if (!(area > 0)) return;
  auto& d = c.reflection_scratch;  // per node: sum_f A_f q_f F_fg, then the change [W]
  for (int k = 0; k < 2; ++k) {
    for (size_t i = 0; i < faces.size(); ++i) mean[k] += areas[i] * c.face_flux[c.fi(faces[i])][k];
    mean[k] /= area;
    // change into g: q_m sum_f A_f F_fg - sum_f A_f q_f F_fg = sum_f A_f (q_m - q_f) F_fg
    for (size_t i = 0; i < faces.size(); ++i) {
      const double w = areas[i] * (mean[k] - c.face_flux[c.fi(faces[i])][k]);
      for (const auto& [g, fr] : c.face_view[c.fi(faces[i])][k]) {
        if (d[g] == 0.0 && std::find(touched.begin(), touched.end(), g) == touched.end()) touched.push_back(g);
        d[g] += w * fr;
      }
    }
    // The mean view: sum_f A_f F_fg / A, over the nodes any changed face sees.
    thread_local std::vector<double> view;
    view.assign(d.size(), 0.0);
    std::vector<int> seen;
    for (size_t i = 0; i < faces.size(); ++i)
      for (const auto& [g, fr] : c.face_view[c.fi(faces[i])][k]) {
        if (view[g] == 0.0) seen.push_back(g);
        view[g] += areas[i] * fr / area;
      }
    std::sort(seen.begin(), seen.end());
    for (int g : seen) mean_view[k].emplace_back(g, view[g]);
  }
}

bool NodeCollapse::reflection_within_cap(Context& c) const {
  if (c.face_flux.empty()) return true;
  std::array<double, 2> mean;
  std::array<Context::View, 2> mean_view;
  thread_local std::vector<int> touched;
  bool ok = true;
  for (const auto& d : area_delta_) {
    reflection_change(c, d.key, mean, mean_view, touched);
    for (int g : touched) {
      const size_t at = static_cast<size_t>(d.key) * c.reflection_scratch.size() + g;
      const double before = c.node_reflection_change_W[at], after = before + c.reflection_scratch[g];
      if (std::abs(after) > c.reflection_cap_W(g) && std::abs(after) > std::abs(before)) ok = false;
      c.reflection_scratch[g] = 0.0;
    }
    if (!ok) return false;
  }
  return true;
}

void NodeCollapse::record_reflection_change(Context& c) const {
  if (c.face_flux.empty()) return;
  std::array<double, 2> mean;
  std::array<Context::View, 2> mean_view;
  thread_local std::vector<int> touched;
  for (const auto& d : area_delta_) {
    reflection_change(c, d.key, mean, mean_view, touched);
    const size_t row = static_cast<size_t>(d.key) * c.reflection_scratch.size();
    for (int g : touched) c.node_reflection_change_W[row + g] += c.reflection_scratch[g], c.reflection_scratch[g] = 0.0;
    for (const VFace* f : c.projection_faces) {  // the changed faces just measured
      c.face_flux[c.fi(f)] = mean;
      c.face_view[c.fi(f)] = mean_view;
    }
  }
}

}  // namespace thermodec::collapse
