#pragma once
//! NASTRAN bulk data (.bdf .nas .dat) as a mesh input: what read_mesh does not carry in a Mesh.
//! read_mesh reads the geometry (GRID, CTRIA3, CQUAD4 split into two triangles), the property
//! id of each element as its thermal node and the PSHELL's material id as its material; this
//! header gives the RADM thermo-optical properties of those materials, which bare-mesh loading
//! (nodes/load_model.h) turns into model materials. Dialects: small-field (8 columns), large-field
//! (`GRID*`, 16 columns) and free-field (commas), with `+`/`*`/blank continuations. Units are the
//! file's (the model's unit_scale applies). Details: docs/exchange.md, "NASTRAN import".
#include <filesystem>
#include <string>
#include <vector>

namespace thermodec {

//! The RADM card of one material: solar absorptivity and IR emissivity (both in (0, 1]).
struct BdfRadiationProperties {
  std::string material;      //!< material name as read_mesh names it (comment name or "MAT<id>")
  double absorptivity = 0.0;
  double emissivity = 0.0;
};

//! True for the extensions read as NASTRAN bulk data: .bdf .nas .dat (case-insensitive).
bool is_nastran_path(const std::filesystem::path& path);

//! RADM properties of the materials read_mesh(path) names (RADM id = the PSHELL's MID1).
//! \throw IOError if unreadable; InvalidInput (file, line, card) on a malformed RADM.
std::vector<BdfRadiationProperties> read_bdf_radiation_properties(const std::filesystem::path& path);

}  // namespace thermodec
