#pragma once
//! Mesh readers and writers: OBJ (`g`/`o` groups -> nodes, `usemtl` -> materials), PLY ascii
//! and binary (face properties `node`, `material`, `back_material`; float `quality` read as node
//! id for MeshLab interop) and STL ascii and binary. Format chosen by file extension.
#include <filesystem>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

struct MeshReadOptions {
  //! Vertices closer than this are merged [file units]; < 0 disables welding. STL always
  //! needs welding (it stores each triangle's corners separately).
  double weld_tolerance = 1e-9;
  //! Drop zero-area faces (reported on stderr with their indices) instead of failing.
  bool drop_degenerate_faces = true;
};

//! Reads a mesh. face_node/face_material are -1 where the file has no group/material.
//! \throw IOError if the file cannot be opened; InvalidInput for malformed content, with
//! file name and line (text) or face index (binary): NaN/inf coordinates, out-of-range or
//! negative indices, truncated binary data, empty files.
Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options = {});

//! Writes a mesh atomically, format from extension (.obj .ply .stl). Groups and materials
//! are kept where the format can hold them.
//! \throw IOError on write failure; InvalidInput on an unknown extension.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace thermodec
