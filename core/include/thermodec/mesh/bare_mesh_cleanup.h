#pragma once
//! Cleanup of a bare CAD/printable mesh (STL without groups or sidedness) before it becomes a
//! thermal model: what makes the Monte Carlo radiation of such meshes noisy and
//! non-reciprocal, fixed once where the mesh is loaded (docs/reduction.md, "Bare meshes").
//!
//! 1. repair_mesh (mesh/repair.h): weld, drop degenerate faces, conform T-junctions, orient
//!    consistently, closed parts outward. Its index-duplicate removal is replaced by step 2.
//! 2. Faces on the same three vertices: a same-orientation copy is dropped. An
//!    opposite-orientation pair is the contact of two touching solids (welded together) when
//!    the surface around it closes without it (every rim edge keeps two other faces): both
//!    faces are dropped, as in step 4. Otherwise it is a sheet exported as two back-to-back
//!    one-sided faces and becomes one two-sided face, so both sides still radiate.
//! 3. Sidedness of open sheets: a face of an edge-connected component with open (boundary)
//!    edges is made two-sided with its front material on the back. A one-sided open sheet is
//!    transparent from behind (rays pass through one-sided backs), so A sees C through B while
//!    C's rays stop on B: the view factors lose reciprocity and their symmetrisation becomes
//!    seed-dependent. Closed parts stay one-sided (their inside never radiates), unless step 5
//!    finds something inside them.
//! 4. Coincident opposite faces of touching parts (one-sided faces facing each other within
//!    coincident_relative_distance, not sharing their vertices): faces whose sample points lie
//!    on such a face are dropped. Their rays start on (or just beyond) the other part's face,
//!    so whether they hit it is decided by float rounding, ray by ray; the contact area is
//!    inside the assembly and radiates nowhere.
//! 5. Closed parts with faces of other parts inside them (mesh/enclosing_shells.h) are hollow
//!    structures: all their faces are made two-sided with their front material on the back, so
//!    their walls radiate into the cavity and stop the rays of the faces inside, which then
//!    exchange with the walls and each other only. One-sided, the walls let those rays out
//!    through their backs to faces whose rays never come back, and the couplings of the inside
//!    faces depend on the ray counts. Found on the mesh entering step 4, applied after step 6.
//! 6. Two-sided faces lying in the plane of a larger two-sided face (mesh/overlapping_sheets.h)
//!    are dropped: where sheets overlap they are one surface. Both layers would emit from the
//!    same place while a ray meeting them stops on one by a tie rule, so the other would
//!    radiate without ever being hit.
#include <Eigen/Core>
#include <string>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

struct BareMeshCleanupOptions {
  //! Weld and degeneracy tolerance relative to the bounding-box diagonal (repair_mesh).
  double relative_tolerance = 1e-7;
  bool repair = true;                  //!< step 1
  bool merge_duplicate_faces = true;   //!< step 2
  bool two_sided_open_sheets = true;   //!< step 3
  bool drop_coincident_faces = true;   //!< steps 4 and 6
  bool two_sided_enclosing_shells = true;  //!< step 5
  //! Step 4: two faces are coincident when parallel (|cos| > 1 - 1e-4) and their planes are
  //! closer than this fraction of the bounding-box diagonal. Step 5: a point this close to a
  //! closed part's face is on it, not inside.
  double coincident_relative_distance = 1e-5;
};

//! What the cleanup changed (counts, all relative to the faces entering that step).
struct BareMeshCleanupReport {
  int faces_in = 0, faces_out = 0;
  int vertices_welded = 0;
  int degenerate_faces_dropped = 0;
  int t_junctions_split = 0;
  int faces_flipped = 0;
  int duplicate_faces_dropped = 0;           //!< same vertices, same orientation
  int back_to_back_pairs_merged = 0;         //!< same vertices, opposite: one two-sided face each
  int open_sheet_faces_made_two_sided = 0;
  int open_components = 0, closed_components = 0;  //!< edge-connected parts after repair
  int coincident_faces_dropped = 0;         //!< touching faces, steps 2 and 4
  double coincident_area_dropped_m2 = 0.0;
  int overlapping_sheet_faces_dropped = 0;  //!< step 6
  double overlapping_sheet_area_dropped_m2 = 0.0;
  int enclosing_shells = 0;            //!< step 5: closed parts with faces inside
  int shell_faces_made_two_sided = 0;  //!< their faces (not two-sided before)
  int enclosed_faces = 0;              //!< faces of other parts inside them (found before step 4)
  bool changed() const;
  //! One line per non-zero count, e.g. "open-sheet faces made two-sided: 2900".
  std::string summary() const;
};

struct BareMeshCleanupResult {
  Mesh mesh;
  Eigen::VectorXi source_face;  //!< #F_out input face of each output face
  //! #F_out 1 = the face must radiate from both sides (steps 2, 3, 5). Where its front material is
  //! known (>= 0) face_back_material already says so; a face whose front is -1 ("the node's
  //! material", resolved later) needs the loader to give its back the resolved front.
  Eigen::VectorXi two_sided;
  BareMeshCleanupReport report;
};

//! Cleans `mesh` (see the steps above). face_node/face_material follow their faces.
//! Deterministic: the result depends only on the mesh.
//! \throw InvalidInput on NaN/inf coordinates, out-of-range indices or a negative tolerance.
BareMeshCleanupResult cleanup_bare_mesh(const Mesh& mesh, const BareMeshCleanupOptions& options = {});

}  // namespace thermodec
