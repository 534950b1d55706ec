#pragma once
//! Mesh repair before decimation (the paper's preprocessing, Fig. 5): weld coincident vertices,
//! drop degenerate and duplicate faces, make non-conforming tessellations conforming by
//! recursive edge bisection at T-junctions, orient faces consistently where the surface allows
//! it, and report (never fail on) non-manifold edges and vertices.
#include <Eigen/Core>
#include <string>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

struct RepairOptions {
  //! Vertices closer than weld_tolerance * (bounding-box diagonal) are merged; a vertex closer
  //! than that to an edge's interior is a T-junction. Must be >= 0.
  double relative_tolerance = 1e-7;
  bool weld = true;
  bool drop_degenerate = true;
  bool drop_duplicates = true;
  bool conform_t_junctions = true;
  //! Flip faces so that neighbours across manifold edges agree, then make closed components
  //! enclose positive volume (outward normals). Two-sided faces flip with their front and back
  //! materials swapped, so the physics does not change.
  bool orient = true;
};

//! What repair changed (counts) and what it left alone.
struct RepairReport {
  int vertices_welded = 0;          //!< vertices merged into an earlier one
  int degenerate_faces_dropped = 0; //!< repeated corners or zero area
  int duplicate_faces_dropped = 0;  //!< same three vertices as an earlier face
  int t_junctions_split = 0;        //!< edge bisections at T-junction vertices
  int faces_flipped = 0;
  int orientation_conflicts = 0;    //!< manifold edges still traversed twice the same way
  int unreferenced_vertices_removed = 0;
  int non_manifold_edges = 0;       //!< edges with more than two faces (kept, reported)
  int non_manifold_vertices = 0;    //!< vertices whose faces form several fans (kept)
  int open_edges = 0;               //!< edges with a single face after repair
  bool changed() const {
    return vertices_welded || degenerate_faces_dropped || duplicate_faces_dropped ||
           t_junctions_split || faces_flipped || unreferenced_vertices_removed;
  }
  //! One line per non-zero count, e.g. "welded 12 vertices".
  std::string summary() const;
};

struct RepairResult {
  Mesh mesh;
  //! #F_out: the input face each output face comes from (split faces share their parent).
  Eigen::VectorXi source_face;
  RepairReport report;
};

//! Repairs `mesh` (see RepairOptions). Per-face node and materials follow their faces.
//! \throw InvalidInput on NaN/inf coordinates, out-of-range indices or a negative tolerance.
RepairResult repair_mesh(const Mesh& mesh, const RepairOptions& options = {});

}  // namespace thermodec
