// The face sides as the load rays see them (load_sides.h).
#include "load_sides.h"

namespace thermodec::load_rays {

std::vector<Side> side_geometry(const Mesh& mesh, const SurfaceSides& sides) {
  std::vector<Side> out(sides.size());
  for (int s = 0; s < sides.size(); ++s) {
    const int f = sides.face[s];
    Side& g = out[s];
    g.a = mesh.V.row(mesh.F(f, 0)).transpose();
    g.b = mesh.V.row(mesh.F(f, 1)).transpose();
    g.c = mesh.V.row(mesh.F(f, 2)).transpose();
    const Eigen::Vector3d n = (g.b - g.a).cross(g.c - g.a);
    g.area = 0.5 * n.norm();
    g.normal = n.normalized();
    if (sides.is_back[s]) {
      g.normal = -g.normal;
      std::swap(g.b, g.c);  // keep the (a, b, c) winding counter-clockwise seen from this side
    }
    // note: like the view-factor rays, the lift depends on this face only (not on the scene
    // extent), so an unchanged face casts bit-identical rays in a decimated model.
    g.offset = 1e-5 * std::max({g.a.cwiseAbs().maxCoeff(), g.b.cwiseAbs().maxCoeff(), g.c.cwiseAbs().maxCoeff(),
                                (g.b - g.a).norm(), (g.c - g.a).norm()});
    const Eigen::Vector3d lifted = g.a + g.offset * g.normal, e1 = g.b - g.a, e2 = g.c - g.a;
    for (int k = 0; k < 3; ++k) {
      g.fa[k] = float(lifted[k]);
      g.fe1[k] = float(e1[k]);
      g.fe2[k] = float(e2[k]);
      g.fn[k] = float(g.normal[k]);
    }
  }
  return out;
}

}  // namespace thermodec::load_rays
