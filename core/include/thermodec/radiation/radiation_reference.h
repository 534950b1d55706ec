#pragma once
//! Incremental radiative couplings for the reduction driver, which compares one reference
//! model with hundreds of candidates that differ from it in one or a few nodes.
//!
//! prepare_radiation() traces the reference once and keeps everything (Embree scene, integer
//! hit counts per face, Gebhart solution). radiative_couplings_incremental() then finds which
//! faces of a candidate changed (by their stable identity: vertex coordinates + side, so no
//! list of changed nodes is needed), traces all rays of the changed faces, and for unchanged
//! faces re-traces only the rays that meet the changed geometry (the removed and the added
//! faces: a bounding-box test first, then an exact segment test against a small Embree scene
//! of those faces, up to the ray's reference hit), in the candidate scene (and, without ray
//! records, in the reference scene to subtract them). Every other ray would hit the same face in both models, so
//! its reference count is reused as is. The view factors are therefore *identical* to a full
//! recompute of the candidate with the same settings (same rays, same hits), and the Gebhart
//! solve is warm-started from the reference solution.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/rays/ray_scene.h"

namespace thermodec {

//! Expensive, reusable state of a reference model (non-copyable, movable).
class RadiationReference {
 public:
  RadiationReference(RadiationReference&&) noexcept;
  RadiationReference& operator=(RadiationReference&&) noexcept;
  ~RadiationReference();

  const ThermalModel& model() const;
  const RadiationSettings& settings() const;
  const FaceViewFactors& face_view_factors() const;
  const GebhartFactors& gebhart() const;  //!< IR, groups = node_groups(sides, #nodes)
  const NodeCouplings& couplings() const;
  //! Bytes of the per-ray records kept (0 if they did not fit their budget), and what all
  //! of them take (20 bytes a ray, see prepare_radiation).
  std::size_t record_bytes() const;
  std::size_t record_bytes_needed() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  explicit RadiationReference(std::unique_ptr<Impl> impl);
  friend RadiationReference prepare_radiation(const ThermalModel&, const RadiationSettings&, std::size_t);
  std::unique_ptr<Impl> impl_;
};

//! Traces `reference` fully (as radiative_couplings) and keeps the state for reuse. Each
//! ray's first hit (8 bytes), compressed direction and origin (4 bytes each) and place in the
//! side's direction-cell order (4 bytes) are kept too when all fit in `max_record_bytes`
//! (20 bytes a ray: the sample's 6.9 M rays take 138 MB, NPP_16's 24 M 0.5 GB; the default
//! keeps up to 94 M rays, as many as before the origins were kept): candidates then
//! re-trace only rays that reach the changed region before their reference hit, and only in
//! the candidate scene; without records, every ray meeting the region's box is traced in both.
//! \throw InvalidInput as radiative_couplings.
RadiationReference prepare_radiation(const ThermalModel& reference, const RadiationSettings& settings,
                                     std::size_t max_record_bytes = std::size_t(7) << 28);

//! What prepare_radiation(reference, settings, max_record_bytes) keeps for its ray records
//! (RadiationReference::record_bytes()) [bytes], known before any ray is traced: a caller can
//! size what it runs beside the tracing by it.
std::size_t ir_record_bytes_kept(const ThermalModel& reference, const RadiationSettings& settings,
                                 std::size_t max_record_bytes);

//! What an incremental evaluation reused and re-traced.
struct IncrementalStats {
  int changed_sides = 0;            //!< candidate sides without a twin in the reference (traced fully)
  int removed_sides = 0;            //!< reference sides without a twin in the candidate
  int reused_sides = 0;             //!< unchanged sides (reference counts reused)
  //! of those, the sides none of whose rays can meet the change: their rows copied as they are
  int rows_kept = 0;
  std::int64_t rays_retraced = 0;   //!< rays traced (both scenes counted)
  std::int64_t rays_total = 0;      //!< rays a full recompute would trace
  Eigen::AlignedBox3d changed_box;  //!< region whose geometry changed [m]
  //! The removed (reference) and added (candidate) triangles, for exact "does this ray meet
  //! the change" tests (LoadReuse::changed_faces).
  Mesh changed_faces;
  //! Unchanged sides traced whole because a ray kept a hit on a removed face (a filter that
  //! should have sent it to be traced again did not): the result is still exact; 0 expected.
  int sides_traced_whole = 0;
};

//! What differs between the reference's mesh and `candidate`'s, found by face identity
//! (SurfaceSides::key) as radiative_couplings_incremental finds it (the same box and faces as
//! its IncrementalStats), without tracing anything: so a trial can start its loads, which
//! reuse rays outside this region, alongside the couplings.
struct GeometryChange {
  Eigen::AlignedBox3d box;  //!< of the removed and the added faces [m]; empty: nothing changed
  Mesh faces;               //!< the removed (reference) and the added (candidate) triangles
};
GeometryChange geometry_change(const RadiationReference& reference, const ThermalModel& candidate);

//! Couplings of `candidate` with the reference's settings, reusing the reference's rays.
//! Equal to radiative_couplings(candidate, reference.settings()) up to the Gebhart solver
//! tolerance (view factors bit-identical). `face_vf`, if non-null, receives the candidate's
//! face-level view factors. `candidate_scene` (optional): the candidate mesh's scene, if the
//! caller has it (a trial traces its loads in it too); else one is built.
//! \throw InvalidInput as radiative_couplings.
NodeCouplings radiative_couplings_incremental(const RadiationReference& reference, const ThermalModel& candidate,
                                              IncrementalStats* stats = nullptr, FaceViewFactors* face_vf = nullptr,
                                              const RayScene* candidate_scene = nullptr);

}  // namespace thermodec
