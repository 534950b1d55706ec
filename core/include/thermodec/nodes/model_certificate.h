#pragma once
//! The verification a reduced model carries with it (plain data): where it came from and how
//! far from its original it was verified to be. `reduce` writes it into the reduced model.json
//! ("certificate"); every export of the model repeats it in its header comment, and `info`
//! shows it, so that the figure does not stay behind with report.json.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace thermodec {

struct ModelCertificate {
  std::string original_model;       //!< path of the model the reduction started from
  std::string original_sha256;      //!< SHA-256 (hex) of that model file's bytes
  std::string original_mesh_sha256; //!< SHA-256 (hex) of its mesh file's bytes (empty if the model is the mesh)
  double tolerance_K = 0.0;         //!< max |dT| the reduction was asked to keep
  std::vector<std::string> cases;   //!< load cases verified (the model's own first)
  double estimate_K = 0.0;          //!< verified max |dT| over nodes, times and cases: estimate
  double standard_error_K = 0.0;    //!< its standard error
  double upper_bound_K = 0.0;       //!< one-sided upper bound at `confidence`
  double confidence = 0.0;          //!< of that bound (e.g. 0.975)
  std::vector<std::uint64_t> seeds; //!< seeds of the verification pairs
  int faces_before = 0, faces_after = 0;
};

//! The certificate as short text lines (no comment marker; a writer prefixes its own), e.g.
//! "reduced from sample_models/satellite/model.json (sha256 3f2a...)".
std::vector<std::string> certificate_lines(const ModelCertificate& certificate);

//! The model file's "certificate" object and back. \throw InvalidInput naming the key at fault.
nlohmann::json certificate_json(const ModelCertificate& certificate);
ModelCertificate certificate_from_json(const nlohmann::json& json);

//! SHA-256 of a file's bytes as 64 hex digits. \throw IOError if unreadable.
std::string file_sha256(const std::string& path);

}  // namespace thermodec
