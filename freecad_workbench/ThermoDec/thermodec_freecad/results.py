"""Results back into FreeCAD: a (reduced) mesh read by the core, as a Mesh feature coloured by
node or by temperature, and a short report. simulate/reduce run the core through the binding
once this build of the core has them."""

import json

import numpy as np

import FreeCAD

from . import core, objects, tessellate, units
from .errors import ThermoDecError


def _node_temperatures(temperatures):
    """{node name: K} from a dict or a JSON file holding one (optionally under 'temperatures_K')."""
    if temperatures is None:
        return None
    if isinstance(temperatures, str):
        try:
            with open(temperatures, encoding="utf-8") as f:
                temperatures = json.load(f)
        except (OSError, ValueError) as e:
            raise ThermoDecError("cannot read temperatures from %s: %s" % (temperatures, e)) from None
    if "temperatures_K" in temperatures:
        temperatures = temperatures["temperatures_K"]
    try:
        return {str(k): float(v) for k, v in temperatures.items()}
    except (TypeError, ValueError, AttributeError):
        raise ThermoDecError("temperatures must map node names to kelvin") from None


def import_results(analysis, mesh_path, temperatures=None, name="Results"):
    """Reads `mesh_path` with the core and adds it to the analysis as a Mesh feature with
    per-triangle node (and temperature [K] when `temperatures` maps node names to K, or names
    a JSON file that does). Returns (feature, summary dict)."""
    import Mesh
    td = core.module()
    mesh = td.read_mesh(mesh_path)
    face_node = np.asarray(mesh.face_node)
    if np.any(face_node < 0):
        raise ThermoDecError("%s: %d triangles have no node" % (mesh_path, int(np.sum(face_node < 0))))
    node_names = list(mesh.node_names)
    V = units.points_mm(np.asarray(mesh.V))
    F = np.asarray(mesh.F)
    feature = analysis.Document.addObject("Mesh::FeaturePython", name)
    tessellate.ThermalMesh(feature)
    if FreeCAD.GuiUp:
        from . import viewproviders
        viewproviders.ViewProviderThermalMesh(feature.ViewObject)
    analysis.addObject(feature)
    feature.Mesh = Mesh.Mesh(([FreeCAD.Vector(*p) for p in V], [tuple(int(j) for j in t) for t in F]))
    feature.FaceNode = [int(n) for n in face_node]
    feature.FaceMaterial = [int(m) for m in np.asarray(mesh.face_material)]
    feature.NodeNames = node_names
    feature.MaterialNames = list(mesh.material_names)
    summary = {"mesh": mesh_path, "faces": int(len(F)), "vertices": int(len(V)), "nodes": len(node_names)}

    node_t = _node_temperatures(temperatures)
    if node_t is not None:
        missing = [n for n in node_names if n not in node_t]
        if missing:
            raise ThermoDecError("no temperature for node(s) %s" % ", ".join(missing[:8]))
        face_t = [node_t[node_names[n]] for n in face_node]
        feature.FaceTemperature = face_t
        summary.update(temperature_min_K=min(face_t), temperature_max_K=max(face_t))
    if FreeCAD.GuiUp:
        from . import viewproviders
        if node_t is not None:
            viewproviders.colour_by_temperature(feature, feature.FaceTemperature,
                                                summary["temperature_min_K"], summary["temperature_max_K"])
        else:
            viewproviders.colour_by_node(feature)
    FreeCAD.Console.PrintMessage("ThermoDec results: %s\n" % json.dumps(summary))
    return feature, summary


def simulate(analysis):
    """Thermal simulation of the exported model through the core (when the core has it)."""
    core.require("simulate")
    raise ThermoDecError("simulate is not wired into the workbench yet")


def reduce(analysis):
    """Simulation-driven reduction through the core (when the core has it)."""
    core.require("reduce")
    raise ThermoDecError("reduce is not wired into the workbench yet")
