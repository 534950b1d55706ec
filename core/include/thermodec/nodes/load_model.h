#pragma once
//! Reading and writing the thermal model file (JSON, docs/model-format.md). A bare mesh path
//! (.obj .ply .stl, NASTRAN .bdf .nas .dat with its RADM coatings) is a valid model too: documented defaults apply, and a mesh without
//! groups gets an automatic nodal breakdown.
#include <filesystem>

#include "thermodec/mesh/bare_mesh_cleanup.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"
#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

//! \throw InvalidInput naming the offending key (unknown node or material, negative
//! capacitance, absorptivity/emissivity outside (0,1], ...); IOError if unreadable.
ThermalModel load_model(const std::filesystem::path& path);

//! Same, with explicit mesh reading options (e.g. keep degenerate faces for `thermodec info`).
//! The mesh is taken as read: no bare-mesh cleanup (for tools that inspect the file itself).
ThermalModel load_model(const std::filesystem::path& path, const MeshReadOptions& mesh_options);

struct ModelLoadOptions {
  MeshReadOptions mesh;
  //! A bare mesh without groups (a raw CAD export, e.g. STL, given as the model) is cleaned
  //! before its automatic nodes are built (mesh/bare_mesh_cleanup.h); the counts land in
  //! ThermalModel::mesh_cleanup. So is the mesh of a model file that has no groups and whose
  //! file names no nodes and sets no "radiation" (the same mesh then reduces the same way given
  //! bare or in a model file). Grouped meshes and other model files are never cleaned: their
  //! sidedness and faces are the user's.
  bool clean_bare_mesh = true;
  BareMeshCleanupOptions cleanup;
  //! An unknown key in the model file is an error naming the nearest known key; true makes
  //! it a warning (CLI `--allow-unknown-keys`), e.g. for a file written by a newer version.
  bool allow_unknown_keys = false;
  //! The automatic nodal breakdown of a mesh without groups (CLI `--nodes N` sets max_nodes).
  AutomaticNodeOptions automatic_nodes;
};

//! Same, with all loading options. load_model(path) = load_model(path, ModelLoadOptions{}).
ThermalModel load_model(const std::filesystem::path& path, const ModelLoadOptions& options);

//! Writes `model` as JSON at `json_path` and its mesh at `mesh_path` (relative path stored
//! in the JSON), both atomically.
void save_model(const ThermalModel& model, const std::filesystem::path& json_path,
                const std::filesystem::path& mesh_path);

}  // namespace thermodec
