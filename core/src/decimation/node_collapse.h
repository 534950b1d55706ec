#pragma once
// Private to core/src/decimation: one candidate edge collapse for vcglib's local optimisation,
// whose hooks (node_collapse.cpp) call its cost (collapse_cost.cpp), its vertex placement
// (vertex_placement.cpp) and its constraints (collapse_constraints.cpp).
#include "collapse_types.h"

namespace thermodec::collapse {

class NodeCollapse : public vcg::tri::TriEdgeCollapse<VMesh, VPair, NodeCollapse> {
  using Base = vcg::tri::TriEdgeCollapse<VMesh, VPair, NodeCollapse>;

 public:
  using HeapType = Base::HeapType;
  using HeapElem = Base::HeapElem;

  NodeCollapse(const VPair& p, int mark, vcg::BaseParameterClass* pp) {
    localMark = mark;
    pos = p;
    _priority = ComputePriority(pp);
  }

  bool valid() const { return valid_; }
  //! Why the last evaluation or constraint check refused this collapse (none if it did not).
  CollapseBlock refused() const { return refused_; }

  //! The constraints that depend on the state of the other collapses (budgets, regions, area
  //! and volume bounds, topology), checked when the collapse comes off the heap; sets refused().
  bool constraints_hold(Context& c);

  //! Most vertices on one cross-section loop of a thin tube (section_collapse.cpp).
  static constexpr int kMaxSection = 12;

  ScalarType ComputePriority(vcg::BaseParameterClass* pp) override;

  bool IsUpToDate() const override {
    const VVertex* v0 = pos.cV(0);
    const VVertex* v1 = pos.cV(1);
    return !v0->IsD() && !v1->IsD() && localMark >= v0->cIMark() && localMark >= v1->cIMark();
  }

  // Budgets, regions, area, steep-turn and closed-volume bounds, link condition (collapse_constraints.cpp).
  bool IsFeasible(vcg::BaseParameterClass* pp) override;

  void Execute(VMesh& m, vcg::BaseParameterClass* pp) override;

  void UpdateHeap(HeapType& heap, vcg::BaseParameterClass* pp) override;

  static void push(HeapType& heap, VVertex* a, VVertex* b, Context& c);

  static void Init(VMesh& m, HeapType& heap, vcg::BaseParameterClass* pp);
  static void Finalize(VMesh&, HeapType&, vcg::BaseParameterClass*) {}
  static float HeapSimplexRatio(vcg::BaseParameterClass*) { return 8.0f; }

 private:
  bool is_exact_for(int node) const {
    for (const auto& d : exact_per_node_)
      if (d.key == node) return d.value > 0;
    return false;
  }

  // Clears the candidate for an evaluation of the collapse of `gone` into `kept`.
  void reset(VVertex* gone, VVertex* kept);
  void set_refused(CollapseBlock why) { valid_ = false, refused_ = why; }

  // Does the edge (a, b) separate two regions, or bound the surface (1 face or > 2 faces)?
  static bool is_contour_edge(const Context& c, VVertex* a, VVertex* b);

  // The other contour neighbour of contour vertex v (not `not_this`), or nullptr.
  static VVertex* other_contour_neighbour(const Context& c, VVertex* v, VVertex* not_this);

  // Corners `q` of star face f once this collapse puts its vertex at x, the index `moved_at` of
  // a corner that moved; returns how many moved (2: f is on the collapsed edge and disappears).
  int corners_after(const VFace* f, const Vec3& x, std::array<Vec3, 3>& q, int& moved_at) const;

  // Where the merged vertex goes (x_): the Lindstrom-Turk point when both ends are free
  // (`optimal`), else the kept end, after the contour tests (deviation, straightness, LT
  // boundary cost). False if the collapse is not allowed (vertex_placement.cpp).
  bool place(Context& c, VVertex* gone, VVertex* kept, bool optimal, const Vec3& pg, const Vec3& pk,
             double& boundary_cost, bool& straight);

  // Area-neutral placement of a collapse inside one region (both ends free): moves the
  // Lindstrom-Turk point x_ along the gradient of the star's area until the node's area is
  // back at its input value, or at least the star's own area is unchanged.
  //
  // Why: a node that keeps its heat input radiates it from its area, so a relative area change
  // dA/A moves it by dT = -T dA/(4A) (0.1 % is ~0.07 K at 280 K) whatever its view factors do.
  // On curved parts (CAD cylinders, the dish) every volume-preserving collapse grows the area
  // a little, and the per-node bound then stops the decimation early. Volume matters little
  // thermally (the bound on closed volumes still holds: IsFeasible). The area's gradient is
  // normal to the surface on a curved star and vanishes on a flat one, where the area is
  // preserved anyway; a correction that would move x_ by more than a tenth of the star's edge
  // length is not made (a flat star cannot pay back another collapse's drift without a tent).
  void place_area_neutral(const Context& c);

  // True if collapsing into x keeps the star's closed part within max_relative_volume_change.
  // The LT point x_ keeps the volume; an area-neutral point spends the volume budget, and a
  // collapse refused for volume is lost, so the LT point is kept instead. (Measured on Juno and
  // NPP_16: falling back reaches further than refusing, and than cutting the move short where
  // the volume budget ends.)
  bool keeps_closed_volume(const Context& c, const Vec3& x) const;

  // Evaluates removing `gone` into `kept` (kept moves too when `optimal`): placement, validity,
  // cost and the bookkeeping deltas used by IsFeasible/Execute.
  void evaluate(Context& c, VVertex* gone, VVertex* kept, bool optimal);

  // Link condition Lk(a) n Lk(b) == Lk(ab), written with sorted vectors (no maps) and valid
  // when the kept vertex is non-manifold (frozen): the removed vertex is always manifold.
  bool link_condition(Context& c) const;

  // Thin-tube section collapse (section_collapse.cpp): when `gone` and `kept` lie on two
  // consecutive cross-section loops of a thin tube (loops of n short edges joined by long ones),
  // the whole loop at `gone` moves onto the loop at `kept` in one step, removing the 2n faces
  // between them, so the tube stays a tube instead of being skewed by single collapses.
  struct Section {
    int n = 0;                                   // 0: a single edge collapse
    std::array<VVertex*, kMaxSection> gone{}, kept{};  // gone[j] merges into kept[j]
    Vec3 shift = Vec3::Zero();                   // the kept loop moves by this [m]
    Vec3 centre = Vec3::Zero();                  // the kept loop's centroid [m]
  };

  // The two loops of a section collapse of `gone` into `kept`, aligned so that gone[j] and
  // kept[j] share an edge; false if the edge is not on a thin tube.
  static bool find_section(Context& c, VVertex* gone, VVertex* kept, Section& s);
  // v lies on a cross-section loop of free vertices of a thin tube along its edge to w: a
  // single collapse of that edge would break the loop (and every later section collapse
  // through it).
  static bool on_thin_tube(Context& c, VVertex* v, VVertex* w);
  bool section_topology_ok(Context& c) const;
  // Where vertex v is after the section collapse, the kept loop moved by `shift` [m].
  Vec3 section_position(const VVertex* v, const Vec3& shift) const;
  struct SectionMeasures {
    double area_m2 = 0, volume_change_m3 = 0;
    Vec3 area_gradient = Vec3::Zero(), volume_gradient = Vec3::Zero();  // [m], [m^2]
  };
  SectionMeasures section_measures(const Context& c, const Vec3& shift) const;
  Vec3 section_restoring_shift(const Context& c) const;
  bool section_keeps_volume(const Context& c, const Vec3& shift) const;
  bool section_removes(const VFace* f) const;  // f lies between the two loops

  // Evaluates the section collapse of `gone` into `kept` (validity, cost, deltas, the kept
  // loop's area-restoring shift); false if it is not a valid section collapse.
  bool evaluate_section(Context& c, VVertex* gone, VVertex* kept);

  // Runs the section collapse: n vcg edge collapses, the kept loop moved by its shift.
  void execute_section(VMesh& m, Context& c);

  // Node-area restoration (area_restoration.cpp, DecimationOptions::restore_node_areas): plans
  // the offsets of `node`'s free vertices that bring its area back to its input value once this
  // collapse has run (its area change delta_m2 [m^2]); false if no offset within
  // max_restoring_offset does it or the offsets turn a face too far, degenerate one or take a
  // closed part past its volume bound (volume_delta_ included).
  bool plan_area_restoration(Context& c, int node);
  // Moves the planned vertices (after the collapse), updates the node's area, the parts'
  // volumes and the stamps of the stars that changed.
  void apply_area_restoration(Context& c);
  // The faces around every vertex this collapse (single or section) moves or removes, sorted and
  // unique, into c.projection_faces (projected_area_cap.cpp).
  void gather_faces_around_moved_vertices(Context& c) const;
  // Face f's corners before (p) and after (q) this collapse, single or section [m]
  // (projected_area_cap.cpp).
  void corners_before_after(const VFace* f, std::array<Vec3, 3>& p, std::array<Vec3, 3>& q) const;
  // Adds to dp what this collapse (single or section) does to `node`'s projected area in each
  // direction of Context::projection_directions() [m^2] (projected_area_cap.cpp).
  void add_projection_change(Context& c, int node, Context::Projection& dp) const;
  // With projected_area_cap: node `node`'s projected area stays within its cap in every
  // direction after this collapse (and the restoration planned with it, for that node).
  bool projection_within_cap(Context& c, int node) const;
  // Adds this collapse's projected-area change to each node's account (Execute).
  void record_projection_change(Context& c) const;
  // Reflected-sunlight cap (reflection_cap.cpp): what averaging node `node`'s changed faces
  // does to the reflected power reaching each node (c.reflection_scratch at `touched`), their
  // mean flux and views; whether every node's account stays within its cap; the accounts
  // charged and the changed faces given the means (before the collapse runs).
  void reflection_change(Context& c, int node, std::array<double, 2>& mean, std::array<Context::View, 2>& mean_view,
                         std::vector<int>& touched) const;
  bool reflection_within_cap(Context& c) const;
  void record_reflection_change(Context& c) const;
  struct Restoration {
    int node = -1;                                // -1: none planned
    std::vector<std::pair<VVertex*, Vec3>> moves;  // vertex -> new position [m]
    double area_m2 = 0;                           // the node's area change it makes
    Deltas volume;                                // part -> volume change [m^3]
    std::vector<double> projection;               // its projected-area change per direction [m^2]
  };
  Restoration restore_;

  // Hands each face of `removed` to a surviving face around `kept` (provenance).
  static void record_absorbed(Context& c, const std::vector<int>& removed, VVertex* kept);

  // Every vertex the entry depends on is unchanged since it was evaluated.
  bool is_fresh(const Context& c) const;

  Section section_;
  bool valid_ = false;
  CollapseBlock refused_ = CollapseBlock::none;
  int evaluated_at_ = 0;
  Vec3 x_ = Vec3::Zero();
  Deltas removed_per_node_, removed_per_region_, area_delta_, volume_delta_;
  double kink_m2_ = 0;     // outline area a kinked contour removal sweeps [m^2] (projected_area_budget)
  bool wide_kink_ = false;  // the kink is past max_kinked_contour_deviation (wide_kink_area_fraction)
  Deltas sharp_delta_;    // node -> cost of its steep turns and kink [m^2] (projected_area_budget)
  Deltas exact_per_node_;  // node -> 1 if this collapse leaves its geometry unchanged
};

//! dp[k] += what turning a face's area vector from n0 to n1 [m^2] does to the projected area in
//! direction k of Context::projection_directions() (projected_area_cap.cpp).
void add_projection(const Vec3& n0, const Vec3& n1, Context::Projection& dp);

//! For each node group still above its target after the collapses, how many of its remaining
//! edges each CollapseBlock refuses (decimation_reach.cpp); zeros for the others.
std::vector<std::array<int, kCollapseBlocks>> explain_reach(VMesh& m, Context& c);

}  // namespace thermodec::collapse
