#pragma once
//! Node-to-node IR radiative couplings of a diffuse grey model.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/gebhart_factors.h"

namespace thermodec {

//! How well the Monte Carlo estimate obeys the exact identities (before enforcing them).
//! A pair of nodes whose two ray directions disagree by more than this many standard errors
//! (pooled: from their mean exchange, not from either direction's own count) is not
//! reciprocal by geometry (radiative_couplings.cpp, non_reciprocal_pairs).
constexpr double kNonReciprocalSigma = 6.0;

struct CouplingDiagnostics {
  //! max over node pairs of |A_i F_ij - A_j F_ji| / sqrt(var_ij + var_ji): the raw
  //! reciprocity asymmetry in standard errors (~N(0,1) per pair if the errors are right).
  double view_factor_asymmetry_sigma = 0.0;
  //! max over pairs with GR > 1e-3 max(GR) of |GR_ij - GR_ji| / max(GR_ij, GR_ji), raw.
  double coupling_asymmetry_relative = 0.0;
  double coupling_asymmetry_sigma = 0.0;  //!< same in standard errors
  //! Node pairs whose two directions disagree by more than kNonReciprocalSigma pooled
  //! standard errors (geometry, not noise: e.g. a face inside another body's closed part);
  //! their inverse-variance combination depends on the two nodes' ray counts (docs/radiation.md).
  int non_reciprocal_pairs = 0;
  //! max over nodes of |sum_j F_ij + F_i,space - 1| after symmetrisation (0 before: every ray
  //! is counted once).
  double view_factor_closure_error = 0.0;
  //! max over nodes of |(sum_j GR_ij + GR_i,space) / sum_{k in i} A_k eps_k - 1| after
  //! symmetrisation, before the self-coupling GR_ii is corrected to restore closure exactly
  //! (GR_ii carries no heat); `gebhart_closure_error` is the face-level closure of the solve.
  double coupling_closure_error = 0.0;
  double gebhart_closure_error = 0.0;
  int gebhart_iterations = 0;
  std::int64_t rays_traced = 0;             //!< rays traced for this result
  //! Rays that passed through the back of a one-sided face (it neither emits nor absorbs);
  //! non-zero means an open or inconsistently oriented mesh.
  std::int64_t back_hits_on_one_sided = 0;
  int surface_sides = 0;                    //!< radiating sides (fronts + backs of two-sided faces)
  int untraceable_faces = 0;                //!< zero-area / non-finite faces left out
  double unassigned_area_m2 = 0.0;          //!< area of faces without a node (absorb, not reported)
};

//! Aggregated node quantities; row i = from node i, node order as in ThermalModel::nodes.
struct NodeCouplings {
  Eigen::VectorXd area_m2;                  //!< radiating area per node [m^2] (both sides of two-sided faces)
  Eigen::MatrixXd view_factors;             //!< F_ij, area-weighted over the node's faces [-]
  Eigen::VectorXd to_space;                 //!< F_i,space [-]
  //! GR_ij = sum A_k eps_k B_kl [m^2], symmetric; rows close: sum_j GR_ij + GR_i,space =
  //! sum_{k in i} A_k eps_k (faces without a node aside).
  Eigen::MatrixXd radiative_couplings_m2;
  Eigen::VectorXd to_space_couplings_m2;    //!< GR_i,space [m^2]
  Eigen::MatrixXd view_factors_standard_error;          //!< Monte Carlo 1-sigma of F_ij
  Eigen::MatrixXd radiative_couplings_standard_error;   //!< Monte Carlo 1-sigma of GR_ij [m^2]
  Eigen::VectorXd to_space_standard_error;              //!< 1-sigma of F_i,space
  Eigen::VectorXd to_space_couplings_standard_error;    //!< 1-sigma of GR_i,space [m^2]
  CouplingDiagnostics diagnostics;
};

//! Computes node couplings by Monte Carlo ray tracing with Embree; deterministic for a seed.
//! \throw InvalidInput if settings.rays_per_face < 1, or a face names a missing node/material.
NodeCouplings radiative_couplings(const ThermalModel& model, const RadiationSettings& settings);

//! Aggregates face-level results to nodes: view factors and Gebhart couplings with standard
//! errors (delta method over per-ray variances, see docs/radiation.md), reciprocity enforced
//! by inverse-variance weighting of the two directions, closure and asymmetry reported.
//! \param emissivity #S per-side emissivity. \param gebhart solved with groups = node_groups().
NodeCouplings aggregate_couplings(const FaceViewFactors& vf, const Eigen::VectorXd& emissivity,
                                  const GebhartFactors& gebhart, int num_nodes);

}  // namespace thermodec
