#pragma once
//! An Embree 3 scene over the model's shared mesh, built once and reused by every ray query
//! (view factors, solar shadowing, Earth visibility, external-geometry extraction).
#include <Eigen/Core>
#include <memory>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

class RayScene {
 public:
  //! Builds the scene (robust mode: no leaks through shared edges). Zero-area faces are kept
  //! out of the scene.
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

  const Mesh& mesh() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace thermodec
