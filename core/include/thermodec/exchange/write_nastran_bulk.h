#pragma once
//! NASTRAN bulk data of a model's surface mesh, the geometry exchange format read by Thermal
//! Desktop's FE-mesh importer, ESA's TASverter, Simcenter, FreeCAD FEM, gmsh and meshio.
//! Dialect: GRID* large-field (16-column reals, full precision), elements and properties
//! small-field (8 columns); lengths in m. Cards: GRID*, CTRIA3 (one per face, corner order =
//! the emitting side's normal), PSHELL (one property id per thermal node, or per node and
//! material where a node's faces carry several coatings; MID1 = the material), RADM (absorptivity,
//! emissivity per material). MAT4 is not written: a thermodec model holds lumped capacitances
//! per node, not conductivity or specific heat. `$ thermodec node PID NAME` and
//! `$ thermodec material MID NAME` comments keep the names; read_mesh reads them back.
#include <filesystem>
#include <vector>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

//! Writes `model`'s mesh atomically as NASTRAN bulk data at `path`.
//! \throw InvalidInput if `path` is one of `protected_inputs` or the mesh has unresolved faces;
//! IOError on write failure.
void write_nastran_bulk(const std::filesystem::path& path, const ThermalModel& model,
                        const std::vector<std::filesystem::path>& protected_inputs = {});

}  // namespace thermodec
