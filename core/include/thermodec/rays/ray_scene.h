#pragma once
//! An Embree 3 scene over the model's shared mesh, built once and reused by every ray query
//! (view factors, solar shadowing, Earth visibility, external-geometry extraction).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! One ray of a batch, in single precision as Embree traces it. The ray is
//! origin + t * direction for t in (t_near, t_far); `direction` need not be unit.
struct RayQuery {
  float origin[3];
  float t_near = 0.0f;
  float direction[3];
  float t_far = 1e30f;
};

//! True if face `f` can be traced: all its coordinates are finite and its area is not
//! negligible (twice-area > 1e-12 x longest edge^2). Embree silently ignores the others, so
//! no ray may be emitted from them either.
bool is_traceable_face(const Mesh& mesh, int f);

class RayScene {
 public:
  //! Builds the scene (robust mode: no leaks through shared edges). Zero-area and
  //! non-finite faces are kept out of the scene (see is_traceable_face); they are never hit.
  //! The mesh is copied, so the scene stays valid after `mesh` is destroyed.
  explicit RayScene(const Mesh& mesh);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;
  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;

  //! Closest face hit by origin + t * direction for t in (t_near, t_far); -1 if none.
  //! `t_hit` receives the distance [m] when non-null. `direction` need not be unit.
  int intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                double t_near, double t_far, double* t_hit = nullptr) const;
  //! True if any face blocks the segment origin + t * direction, t in (t_near, t_far).
  bool occluded(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                double t_near, double t_far) const;

  //! Batched closest hits through Embree's stream API (rtcIntersect1M), the fast path for
  //! many rays: face[i] = face hit by rays[i] or -1; t_hit[i] = its distance [m] (+inf if
  //! none) when `t_hit` is non-null. Thread-safe: threads may trace disjoint batches at once.
  void intersect(const RayQuery* rays, std::size_t count, int* face, float* t_hit = nullptr) const;
  void intersect(const std::vector<RayQuery>& rays, std::vector<int>& face,
                 std::vector<float>* t_hit = nullptr) const;
  //! Batched occlusion (rtcOccluded1M): blocked[i] = 1 if rays[i] hits any face, else 0.
  void occluded(const RayQuery* rays, std::size_t count, std::uint8_t* blocked) const;
  void occluded(const std::vector<RayQuery>& rays, std::vector<std::uint8_t>& blocked) const;

  //! Faces in the scene (traceable ones) and faces kept out.
  int num_traced_faces() const;
  int num_skipped_faces() const;
  //! Bounding box [m] of the traceable faces (empty box if none).
  const Eigen::AlignedBox3d& bounds() const;

  const Mesh& mesh() const;

  struct Impl;
  //! The Embree handles (rays/embree_scene.h), for the core's per-ray loops (rays/tracing.h).
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace thermodec
