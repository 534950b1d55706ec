#pragma once
//! Mesh readers and writers: OBJ (`g`/`o` groups -> nodes, `usemtl` -> materials), PLY ascii
//! and binary (face properties `node`, `material`, `back_material`; float `quality` read as node
//! id for MeshLab interop), STL ascii and binary, and NASTRAN bulk data (.bdf .nas .dat, read
//! only: GRID, CTRIA3, CQUAD4; property id -> node, PSHELL material -> material; see
//! mesh/format_bdf.h). Format chosen by file extension
//! (case-insensitive). Details of each format: docs/model-format.md, section "Mesh files".
#include <cstdint>
#include <filesystem>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! Largest mesh file read_mesh accepts [bytes] (1 GiB, about 20 million triangles in binary
//! STL): the whole file is read into memory, so a bigger file, a device such as /dev/zero or
//! a FIFO is refused before reading rather than exhausting memory.
constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{1} << 30;

struct MeshReadOptions {
  //! Vertices closer than this are merged [file units]; < 0 disables welding. STL always
  //! needs welding (it stores each triangle's corners separately): there a negative value
  //! means 0 (exact duplicates only).
  double weld_tolerance = 1e-9;
  //! Drop degenerate faces (repeated corner or zero area, see is_degenerate_face), reported
  //! on stderr with their indices. false keeps them (mesh_stats counts them).
  bool drop_degenerate_faces = true;
};

//! What read_mesh did besides parsing.
struct MeshReadReport {
  int welded_vertices = 0;             //!< vertices removed by welding
  std::vector<int> degenerate_faces;   //!< triangle indices (after fan triangulation, before dropping)
  bool degenerate_faces_dropped = false;
};

//! Reads a mesh. face_node/face_material/face_back_material are -1 where the file has no
//! group/material/back material. Polygons are fan-triangulated (a polygon's triangles keep its
//! corner order).
//! \throw IOError if the file cannot be opened, is not a regular file (folder, FIFO, device)
//! or is larger than kMaxMeshFileBytes; InvalidInput for malformed content, with
//! file name and line (text) or face index (binary): NaN/inf coordinates, out-of-range or
//! negative indices, truncated binary data, empty files (no faces), unknown extension.
Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options = {});

//! Same, filling `report` instead of logging dropped faces to stderr.
Mesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options,
               MeshReadReport& report);

struct MeshWriteOptions {
  //! PLY and STL: binary (little endian) when true, ascii when false. OBJ is always text.
  bool binary = true;
  //! Files that must not be overwritten (the inputs): writing onto one throws InvalidInput.
  std::vector<std::filesystem::path> protected_inputs;
};

//! Writes a mesh atomically, format from extension (.obj .ply .stl). Groups and materials
//! are kept where the format can hold them: OBJ `g`/`usemtl` (+ a `#thermodec back_material`
//! comment for two-sided faces), PLY face properties and `comment thermodec node|material`
//! lines for the names, ascii STL one `solid` per node; binary STL keeps geometry only.
//! \throw IOError on write failure; InvalidInput on an unknown extension or a mesh whose
//! indices or attribute sizes are inconsistent.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh,
                const MeshWriteOptions& options = {});

}  // namespace thermodec
