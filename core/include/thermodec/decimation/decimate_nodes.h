#pragma once
//! Node-preserving, area-preserving decimation of the one shared mesh of a thermal model.
//!
//! Edge collapses on vcglib's local-optimisation framework, with a Lindstrom-Turk style cost
//! and placement (volume preservation, volume optimisation, boundary preservation, triangle
//! shape; P. Lindstrom, G. Turk, "Fast and memory efficient polygonal simplification", 1998),
//! the placement then moved to keep the node's area (area_neutral_placement).
//! Constraints, so that the coarse mesh has the same nodes, the same interfaces and no holes:
//!  - a face never changes node, material or sidedness: "regions" are the sets of faces with
//!    the same (node, material, back material); an edge whose two faces belong to different
//!    regions, an open-boundary edge and a non-manifold edge are *contour* edges;
//!  - a contour is only coarsened along itself: a contour edge collapses only when both ends
//!    lie on the same single contour, the removed vertex stays where the contour was (its
//!    neighbours keep their positions) and it deviates from the new contour segment by at most
//!    `max_contour_deviation` of that segment's length;
//!  - per-node face budgets: a collapse runs only if every node it takes faces from can pay
//!    for them, except nodes whose geometry it leaves exactly unchanged (straight contour,
//!    coplanar faces: `free_exact_contour_collapses`);
//!  - vertices where >= 3 regions (or a region and an open boundary and another region) meet,
//!    non-manifold vertices and the ends of non-manifold edges never move or disappear (with
//!    release_contacts, a flat region a part only touches gets its own free copy of them);
//!  - optionally, on thin tubes a whole cross-section loop collapses at once
//!    (collapse_tube_sections);
//!  - the link condition (Dey-Edelsbrunner) keeps the topology, a normal-deviation test
//!    forbids face flips, and every node's area and every closed component's enclosed volume
//!    stay within the stated relative tolerances of their input values.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! How candidate collapses are ranked (the order in which they run; never whether they may).
enum class CollapseCostKind {
  //! Lindstrom-Turk: swept volume, boundary and triangle-shape terms (shape preservation).
  geometric,
  //! The geometric cost plus `radiative_cost_weight` times the change of each touched node's
  //! projected area over all directions, relative to the node's area (docs/decimation.md):
  //! collapses that tilt or fold a node's surface, and so change what it sees and absorbs,
  //! run last, whatever volume they sweep.
  radiative,
};

struct DecimationOptions {
  //! Ranking of the candidate collapses (collapse_cost.h); the constraints below are the same
  //! for every kind.
  CollapseCostKind collapse_cost = CollapseCostKind::geometric;
  //! radiative: weight of the projected-area term against the geometric one, both
  //! dimensionless (the geometric cost is in units of the bounding-box diagonal^6; the
  //! radiative one is the mean over all directions of the squared change of a node's projected
  //! area, divided by the node's area squared). At 1e6 the radiative term decides wherever it
  //! is not zero, even on a small closed convex part (whose projected area moves only to second
  //! order when its faces tilt), and the geometric cost orders the collapses that leave it zero
  //! (inside flat panels).
  double radiative_cost_weight = 1e6;

  //! Hard bound on |area_after - area_before| / area_before of every node.
  double max_relative_area_change = 0.005;
  //! Per node (model order): its own bound on |area_after - area_before| / area_before,
  //! replacing max_relative_area_change for that node (e.g. from how far its temperature
  //! depends on its area: reduction/area_bounds.h). Empty = max_relative_area_change for every
  //! node; else an entry for every node, each >= 0. The projected-area budget stays
  //! projected_area_budget * max_relative_area_change.
  std::vector<double> node_max_relative_area_change;
  //! Place the vertex of a collapse inside one region where the node's area comes back to
  //! its input value (or at least where the collapse leaves the area unchanged) instead of at
  //! the volume-preserving point, when that moves it by at most a tenth of the local edge
  //! length. A radiating node moves by dT = -T dA/(4A): area, not volume, is what a thermal
  //! model feels; without this, the collapses on curved parts all grow the area a little and
  //! a tight max_relative_area_change stops the decimation early.
  bool area_neutral_placement = true;
  //! Projected-area cap (docs/decimation.md, "Projected-area cap"): every collapse keeps each
  //! node it touches within projected_area_cap * the node's area bound (its
  //! node_max_relative_area_change, else max_relative_area_change) * its input area [m^2] of its
  //! input projected area P(d) = sum_f max(0, N_f . d) (N_f a face's area vector), in each of 64
  //! directions d over the whole sphere (back faces see -d), tracked over all its collapses.
  //! The budget's account (projected_area_budget) then no longer refuses: the steep turns and
  //! kinks it allows (up to max_fold_deg, max_kinked_contour_deviation) run when the cap holds.
  //! Dimensionless, >= 0; 0 = off (the default; 10 in `reduce`).
  double projected_area_cap = 0.0;
  //! Reflected-sunlight cap (docs/decimation.md, "Reflected-sunlight cap"). A face reflects
  //! what lands on it uniformly over its area, so a collapse that merges a lit face with a
  //! shadowed one reflects the lit face's light from the shadowed face's place, which may see
  //! other nodes differently (a plate in a neighbour's shadow then lights that neighbour) while
  //! the node's area, projected area and absorbed power stay as they were. Per input face side
  //! (index 2 f for the front, 2 f + 1 for the back): the orbit-mean solar-band power it reflects
  //! per unit area, (1 - alpha) x incident flux [W/m^2], and the fraction of its diffuse emission
  //! that first hits each node (view_start[s] .. view_start[s + 1] in view_node / view_fraction).
  //! A collapse gives the changed faces of each node it touches their area-weighted mean flux
  //! and views; the reflected power reaching node g then changes by
  //! sum_f A_f (q_mean - q_f) F_fg [W] (minus the covariance of flux and view over the star),
  //! which is added to g's account; a collapse that takes an account past reflection_cap x
  //! g's area bound x node_absorbed_W[g] (further from zero) is refused. Empty = off (the
  //! default; `reduce` passes the reference's); else all sizes consistent, values finite >= 0.
  struct ReflectionData {
    std::vector<double> flux_W_per_m2;  //!< 2 x #faces
    std::vector<int> view_start;        //!< 2 x #faces + 1
    std::vector<int> view_node;         //!< node index of each view entry
    std::vector<double> view_fraction;  //!< F(side, node) [-]
    std::vector<double> node_absorbed_W;  //!< per node, orbit-mean absorbed external power [W]
    bool empty() const { return flux_W_per_m2.empty(); }
  } reflection;
  //! See reflection. Dimensionless, >= 0: the reflected power reaching a node may move by this
  //! multiple of its area bound times what it absorbs (1: as much as the area bound lets its
  //! own emission move).
  double reflection_cap = 1.0;
  //! Node-area restoration (needs projected_area_cap > 0): a collapse that would take one node's
  //! area past its bound may still run when that node's free vertices (off every contour) bring
  //! its area back to its input value: each moves along its own area gradient by a common
  //! fraction s of its shortest edge, |s| <= max_restoring_offset (Newton on the exact area,
  //! planned on the geometry after the collapse). On a curved node that is an offset along the
  //! surface normal spread over the node instead of one vertex's tent; flat parts do not move
  //! (their gradient vanishes); the outline, interfaces and other nodes stay as they are. The
  //! restored node must keep every face within max_normal_deviation_deg of where the collapse
  //! left it, every closed part within max_relative_volume_change and its projected area within
  //! its cap. Off by default, on in `reduce`.
  bool restore_node_areas = false;
  //! With restore_node_areas: the largest offset of a restoring vertex, as a fraction of its
  //! shortest edge (> 0).
  double max_restoring_offset = 0.05;
  //! Hard bound on |volume_after - volume_before| / |volume_before| of every closed part: faces
  //! connected across manifold edges, each of its edges shared by exactly two of its faces (a
  //! closed box stays closed when a fin stands on one of its edges).
  double max_relative_volume_change = 0.005;
  //! A contour vertex may be removed only if its distance to the contour segment that
  //! replaces it is at most this fraction of that segment's length (0.02 ~ 2.3 degrees of kink).
  double max_contour_deviation = 0.02;
  //! A collapse is refused if any surviving face's normal turns by more than this [degrees],
  //! unless the node's projected-area budget (projected_area_budget) pays for the turn.
  double max_normal_deviation_deg = 60.0;
  //! Area-weighted normal and contour check (docs/decimation.md, "Projected-area budget"): a
  //! face may turn past max_normal_deviation_deg (up to max_fold_deg), and a contour vertex may
  //! go beyond max_contour_deviation (up to max_kinked_contour_deviation), when each node touched
  //! pays for it from a budget of at most projected_area_budget * max_relative_area_change * the
  //! node's input area [m^2]: a turn costs |N_after - N_before| (N the face's area vector), a
  //! kink the area of the triangle the outline sweeps. The sum bounds the change of the node's
  //! projected area in every direction (what the Sun, the planet and the other nodes see of it),
  //! so a sliver of negligible area may turn while a large face may not; at 1 the projected area
  //! in any direction moves through these changes by at most what the area bound lets the node's
  //! area move. Dimensionless; 0 = the per-face and per-vertex checks alone.
  double projected_area_budget = 0.0;
  //! Hard limit [degrees] on any face's turn when projected_area_budget > 0 (fold-overs are refused
  //! whatever their area); in (0, 179], max_normal_deviation_deg when that is larger.
  double max_fold_deg = 120.0;
  //! With projected_area_budget > 0: a contour vertex deviating from the new segment by more
  //! than max_contour_deviation, up to this fraction of its length (0.2 ~ 23 degrees of kink),
  //! may still go when every node on the contour pays the triangle the outline sweeps from the
  //! same budget.
  double max_kinked_contour_deviation = 0.2;
  //! With projected_area_budget > 0 and projected_area_cap > 0: a contour vertex deviating by
  //! more than max_kinked_contour_deviation may still go when, for every node on the contour,
  //! the triangle the outline sweeps is at most this fraction of the area the node's area may
  //! move (its area bound x its input area [m^2]). The swept triangle is what the kink does to
  //! the node's area and projected area, and both stay tracked against their bounds; the
  //! relative cap guards the shape of outlines that matter against their node's budget, not
  //! of small parts on a large node (fittings on a solar array's panel). Dimensionless, >= 0;
  //! 0 = off (the default, also in `reduce`: `reduce --wide-kink F`).
  double wide_kink_area_fraction = 0.0;
  //! With wide_kink_area_fraction > 0: a wide kink only on a part (faces connected across
  //! manifold edges) whose input area is at most this fraction of each paying node's input area
  //! (the fittings on a large panel's node, not the node's own outline). Dimensionless; 1 = any
  //! part of the node.
  double wide_kink_part_fraction = 1.0;
  //! Weight of the triangle-shape term relative to the volume terms in the collapse cost.
  double shape_weight = 1e-3;
  //! Ratio (fraction of faces removed) for faces whose node is -1 (e.g. a bare STL).
  double unassigned_ratio = 0.0;
  //! Every node keeps at least this many faces.
  int min_faces_per_node = 1;
  //! Coarsening an interface removes one face on each side of it. When on, a collapse may take
  //! a face from a node that has no budget left (its target is reached, or its ratio is 0)
  //! provided that node's geometry is unchanged: the removed vertex lies on a straight contour
  //! (within `exact_contour_tolerance`) and all of that node's faces around it are coplanar,
  //! so its surface keeps the same outline, area and normals and only loses a face that
  //! degenerates. Such "free" removals are not charged to that node's budget (see
  //! NodeDecimationStats::faces_removed_free) but respect min_faces_per_node (and every
  //! region keeps a face). At least one node must still pay for the
  //! collapse from its own budget. Without this, a node reduced alone (all other ratios 0)
  //! could never coarsen any of its interfaces.
  bool free_exact_contour_collapses = true;
  //! Contacts: where a part only touches a flat region (a sheet standing on a panel along a
  //! non-manifold edge, a part touching a flat face at one vertex), the flat region need not
  //! keep a vertex there: for it the contact is a point on its plane, and its outline, area and
  //! normals (all that radiation sees of it) are the same without that vertex. When on, such a
  //! flat region's faces get their own free copy of each contact vertex (unit normals and one
  //! region within `exact_contour_tolerance`; contact_release.cpp), while the touching part
  //! keeps the vertex, frozen, exactly where it was. A planar panel then goes down to its
  //! outline's minimal triangulation (a body side holding a wing yoke: 6 -> 2 faces) and the
  //! touching part rests on it without sharing its vertices (a T-contact: no face changes node
  //! and no crack opens, but the output is no longer conforming at the contact; copies left
  //! unmoved are joined back). Off by default (`decimate`'s output stays conforming), on in
  //! `reduce` (reduction_decimation_options).
  bool release_contacts = false;
  //! Near contacts of two nodes: a vertex within this fraction of its shortest edge (and 1e-4
  //! of the bounding-box diagonal) of a nearly parallel face of another node that does not
  //! contain it (a hinge's end disc in the plane of the wall it is fixed to, a bracket
  //! millimetres off a panel) is frozen. Across such a gap what each side
  //! sees of the other is decided at the gap's scale, far below the edges', so moving the vertex
  //! by a fraction of an edge moves the two nodes' radiative coupling at first order (NPP_16:
  //! three collapses of a hinge 2-7 mm off a box wall, +1.08 m^2 of coupling, +0.16 K;
  //! docs/decimation.md, "Near contacts"). 0 = off (the default here; `reduce` uses 0.05).
  double near_contact_fraction = 0.0;
  //! Passes over the mesh: a collapse refused when it comes off the heap (a neighbour had no
  //! budget left, a node's area had drifted to its bound) is queued again only when its star
  //! changes, so the first pass can end while allowed collapses remain (NodeDecimationStats
  //! counts them as `none`). Each further pass queues every remaining edge again, and runs
  //! only if the previous one collapsed something. Same constraints in every pass. At ratio
  //! 0.9 (bench_decimation_reach, area 7.5e-4) 4 passes reach NPP_16 1180 -> 1112 faces and
  //! Juno 5311 -> 4781, but NPP_16's largest change of a node's projected area doubles
  //! (5.4e-2 -> 1.1e-1, docs/benchmarks.md), so the default stays 1 (>= 1).
  int passes = 1;
  //! Thin tubes (struts, ribs, booms, cables: a loop of n <= 12 short edges swept along long
  //! ones) are coarsened a whole cross-section at a time: the loop at the removed vertex moves
  //! onto the next loop along the tube and the 2n faces between them disappear. A single edge
  //! collapse there would drag one corner a whole segment along a curved tube and tilt the
  //! tube's thin side faces past max_normal_deviation_deg, so curved thin tubes could not be
  //! coarsened at all. The kept loop moves out of the bend so that the collapse keeps the
  //! node's area and the closed part's volume (a chord is shorter than the arc it replaces).
  //! Same constraints as any collapse. Off by default: on tdrs' dish ribs it reaches much
  //! further, but each removed cross-section moved the ribs' temperatures 2-5x more than the
  //! single collapses it replaces (docs/decimation.md), so `reduce` does not use it.
  bool collapse_tube_sections = false;
  //! "Thin" for collapse_tube_sections: every cross-section edge is shorter than this fraction
  //! of the collapsed edge along the tube.
  double tube_section_ratio = 0.5;
  //! "Exact" for free_exact_contour_collapses, dimensionless: the removed vertex deviates from
  //! the new contour segment by at most this fraction of the segment's length, every face of
  //! the unpaying node around it has a unit normal within this distance (~ radians) of the
  //! others', and that node's area around the vertex changes by at most this fraction.
  double exact_contour_tolerance = 1e-6;
};

//! Why a collapse that would remove a node's faces is refused (decimation reach).
enum class CollapseBlock : int {
  neighbour_budget,   //!< another node on the edge has spent its face budget
  last_region_face,   //!< a region (node, material, back material) would lose its last face
  area_bound,         //!< a node's area would leave max_relative_area_change
  volume_bound,       //!< a closed part's volume would leave max_relative_volume_change
  contour_deviation,  //!< an interface or boundary vertex is a kink beyond max_contour_deviation
  frozen_vertices,    //!< both ends frozen or on contours, not along one contour
  normal_deviation,   //!< a face would turn past max_normal_deviation_deg (max_fold_deg) or degenerate
  topology,           //!< link condition (the collapse would change the topology)
  thin_tube,          //!< an edge along a thin tube's cross-section loop (collapse_tube_sections)
  projected_area_budget,  //!< the node's steep-turn budget (projected_area_budget) is spent
  reflected_sunlight,  //!< the node has moved its reflection_cap's worth of reflected sunlight
  none,               //!< allowed: the node stopped at its target, not against a constraint
};
constexpr int kCollapseBlocks = static_cast<int>(CollapseBlock::none) + 1;
//! "area_bound", "contour_deviation", ...: the enumerator's name.
const char* collapse_block_name(CollapseBlock block);

//! What decimation did to one node (index = node index; the last entry is the unassigned
//! group, face_node == -1, when the input has such faces).
struct NodeDecimationStats {
  int faces_before = 0;
  int faces_after = 0;
  int target_faces = 0;         //!< faces_before minus the requested removal (rounded)
  double area_before_m2 = 0.0;
  double area_after_m2 = 0.0;
  bool reached = false;          //!< faces_after <= target_faces
  //! Faces this node lost "for free", after its budget was spent (or at ratio 0), to
  //! neighbours' collapses on straight contours that leave its geometry unchanged
  //! (DecimationOptions::free_exact_contour_collapses). Included in faces_after, which is
  //! therefore lower than faces_before for such a node even at ratio 0, and can be lower than
  //! target_faces.
  int faces_removed_free = 0;
  //! Reach: when the node ends above its target, for each CollapseBlock, how many of the
  //! edges of its remaining faces are refused for that reason (the first failing check, in
  //! the order evaluated: budgets and vertex classes, contour, normals, then region, area,
  //! volume, topology); all zero when the node reached its target.
  std::array<int, kCollapseBlocks> blocked_edges{};
  //! The reason that refuses most of this node's remaining edges (none if reached).
  CollapseBlock stopped_by() const;
  double relative_area_change() const {
    return area_before_m2 > 0 ? (area_after_m2 - area_before_m2) / area_before_m2 : 0.0;
  }
};

struct DecimationResult {
  //! The coarse mesh: surviving faces keep their node, material and back material; vertices
  //! on interfaces and frozen corners keep their exact input coordinates.
  Mesh mesh;
  //! #F_coarse: the input face each coarse face is (collapses keep faces, moving corners).
  Eigen::VectorXi fine_face_of_coarse;
  //! #F_fine: the coarse face that absorbed each input face (same node whenever possible;
  //! itself for surviving faces).
  Eigen::VectorXi coarse_face_of_fine;
  //! #V_coarse: the input vertex each coarse vertex is (interface vertices keep their input
  //! coordinates exactly; free vertices may have moved).
  Eigen::VectorXi fine_vertex_of_coarse;
  //! One entry per node (+1 for the unassigned group when present).
  std::vector<NodeDecimationStats> nodes;
  //! Enclosed volume [m^3] of each closed part (see max_relative_volume_change; open ones are
  //! left out), before and after, in order of their smallest input face index.
  std::vector<double> closed_volume_before_m3, closed_volume_after_m3;
  int collapses = 0;
};

//! Decimates each node to its own ratio in one pass over the shared mesh.
//! \param target_ratio_per_node #N fraction of each node's faces to REMOVE (0 = keep all,
//!        0.9 = keep 10 %), N >= number of nodes referenced by face_node (node_names.size()
//!        when larger). A node reaches its target unless the constraints forbid further
//!        collapses; `reached` says which did. A node may end below its target (even at
//!        ratio 0) only through geometry-preserving free removals (faces_removed_free).
//! Deterministic: the same input gives bit-identical output. Thread-safe (no global state).
//! \throw InvalidInput if a ratio is outside [0, 1], a tolerance is negative, sizes mismatch,
//!        or an index is invalid.
DecimationResult decimate_nodes(const Mesh& mesh, const Eigen::VectorXd& target_ratio_per_node,
                                const DecimationOptions& options = {});

//! Decimates to a global ratio with the paper's rule (node_ratios_for_global_ratio): the
//! ratios are computed from the face counts, and when constraints stop a node short of its
//! ratio, its deficit is handed to the next larger nodes and the decimation rerun from the
//! input (at most `max_rounds` rounds; no rerun once the total is within one face per node of
//! global_ratio). Unassigned faces (node -1) form one more group.
//! \throw InvalidInput if global_ratio is outside [0, 1) or the mesh is invalid.
DecimationResult decimate_to_global_ratio(const Mesh& mesh, double global_ratio,
                                          const DecimationOptions& options = {},
                                          int max_rounds = 3);

}  // namespace thermodec
