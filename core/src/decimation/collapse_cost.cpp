// The cost of a candidate collapse: the order in which the valid collapses run.
//
// geometric: Lindstrom-Turk (volume preservation and optimisation, boundary preservation,
// triangle shape), in length^6, made scale-free by 1 / (bbox diagonal)^6 because vcg's heap
// stores float priorities.
//  P. Lindstrom, G. Turk, "Fast and memory efficient polygonal simplification", IEEE Vis 1998.
//
// radiative: what a thermal node exchanges with its surroundings at a distance (the Sun, the
// planet, far nodes) goes through its projected area P(d) = sum_f max(0, N_f . d) in each
// direction d, N_f being a face's area vector. A collapse that keeps the shape in the volume
// sense may still tilt or fold area (a crease flattened on a thin fin, a ridge cut on a
// corrugated panel) and change P in some directions: the node then absorbs and sees
// differently. The term is the mean over the unit sphere of (P_after(d) - P_before(d))^2,
// relative to the node's area squared. Its closed form uses the degree-1 arc-cosine kernel
// (Cho & Saul, "Kernel methods for deep learning", 2009): for a direction uniform on the
// sphere, E[max(0, a.d) max(0, b.d)] = (|a x b| + (pi - theta) a.b) / (6 pi), theta the angle
// between a and b; no direction sampling, so no aliasing and no seed. Back faces see P(-d),
// whose sphere mean is the same, so one term covers one- and two-sided nodes.
#include "collapse_cost.h"

#include <array>
#include <cmath>
#include <vector>

namespace thermodec::collapse {
namespace {

// E over d uniform on the unit sphere of max(0, a.d) max(0, b.d) [m^4 for area vectors].
double arccos_kernel(const Vec3& a, const Vec3& b) {
  const double cross = a.cross(b).norm(), dot = a.dot(b);
  const double theta = std::atan2(cross, dot);
  return (cross + (M_PI - theta) * dot) / (6.0 * M_PI);
}

double geometric_cost(const Context& c, const StarChange& s) {
  double vol_cost = 0, vol_change = 0;
  for (const auto& f : s.faces) {
    vol_cost += f.swept_m3 * f.swept_m3;
    vol_change += f.swept_m3;
  }
  double cost = vol_cost + vol_change * vol_change + s.boundary_m6;
  if (s.shape_m2 != 0.0) {
    const double mean_area = s.star_area_m2 / static_cast<double>(s.star_faces);
    cost += c.opt.shape_weight * s.shape_m2 * (mean_area * mean_area);
  }
  return cost * c.cost_scale;
}

}  // namespace

double projected_area_change(const Context& c, const StarChange& s) {
  // Signed area vectors per node: -N_before for every changed face, +N_after for a survivor.
  struct Term {
    int node;
    double sign;
    Vec3 n;
  };
  // Stars are small, except around the fan centres of CAD meshes (a vertex of 100 faces).
  std::array<Term, 64> small;
  std::vector<Term> large;
  Term* terms = small.data();
  if (2 * s.faces.size() > small.size()) {
    large.resize(2 * s.faces.size());
    terms = large.data();
  }
  int nterms = 0;
  for (const auto& f : s.faces) {
    if (!f.removed && f.after == f.before) continue;
    terms[nterms++] = {f.node, -1.0, 0.5 * (f.before[1] - f.before[0]).cross(f.before[2] - f.before[0])};
    if (!f.removed) terms[nterms++] = {f.node, 1.0, 0.5 * (f.after[1] - f.after[0]).cross(f.after[2] - f.after[0])};
  }
  double total = 0;
  std::array<int, 4> done{};
  int ndone = 0;
  for (int i = 0; i < nterms; ++i) {
    const int node = terms[i].node;
    bool seen = false;
    for (int k = 0; k < ndone; ++k) seen |= done[k] == node;
    if (seen || ndone == 4) continue;
    done[ndone++] = node;
    double sum = 0;  // sum_ij s_i s_j K(N_i, N_j) over this node's terms [m^4]
    for (int a = i; a < nterms; ++a) {
      if (terms[a].node != node) continue;
      sum += terms[a].n.squaredNorm() / 6.0;  // K(N, N) = |N|^2 / 6
      for (int b = a + 1; b < nterms; ++b)
        if (terms[b].node == node) sum += 2.0 * terms[a].sign * terms[b].sign * arccos_kernel(terms[a].n, terms[b].n);
    }
    const double area = c.node_area0[node];
    if (area > 0 && sum > 0) total += sum / (area * area);
  }
  return total;
}

double collapse_cost(const Context& c, const StarChange& change) {
  const double geometric = geometric_cost(c, change);
  if (c.opt.collapse_cost == CollapseCostKind::geometric) return geometric;
  return geometric + c.opt.radiative_cost_weight * projected_area_change(c, change);
}

}  // namespace thermodec::collapse
