"""Export of an analysis as a thermodec model: model.json + OBJ mesh (docs/model-format.md).
The mesh file is written by the core (thermodec.write_mesh), the JSON here.

model_data() gathers everything in SI units (the conversion from FreeCAD's mm happens there,
through units.py, and nowhere else); write_model() writes it; to_thermodec_model() gives the
same data to the core through the pybind11 module.
"""

import json
import os

import numpy as np

import FreeCAD

from . import core, model_file, objects, tessellate, units
from .errors import ThermoDecError
from .files import atomic_write_text


def _environment(env):
    if env.EnvironmentType == "fixed_sun":
        d = env.SunDirection
        if d.Length == 0:
            raise ThermoDecError("environment '%s': SunDirection is the zero vector" % env.Label)
        d = FreeCAD.Vector(d).normalize()  # a copy: the property is left as it is
        return {"type": "fixed_sun", "sun_direction": [d.x, d.y, d.z], "solar_flux": env.SolarFlux}
    return {"type": "orbit", "altitude_km": units.length_km(env.Altitude),
            "inclination_deg": units.angle_deg(env.Inclination), "raan_deg": units.angle_deg(env.RAAN),
            "day_of_year": env.DayOfYear, "attitude": env.Attitude, "albedo": env.Albedo,
            "earth_ir_flux": env.EarthIRFlux}


def model_data(analysis, mesh_file="model.obj"):
    """(json dict, V [m] #Vx3, F #Fx3, face_node #F, face_material #F) of the analysis, SI.

    Tessellates first when the analysis has no ThermalMesh yet. Node and material indices
    of the arrays follow the order of the JSON's nodes/materials."""
    tm = analysis.ThermalMesh
    if tm is None:
        tm = tessellate.tessellate(analysis)
    V_mm, F = tessellate.mesh_arrays(tm)
    face_node = np.array(tm.FaceNode, dtype=np.int64)
    face_material = np.array(tm.FaceMaterial, dtype=np.int64)
    if len(face_node) != len(F) or len(face_material) != len(F):
        raise ThermoDecError("ThermalMesh '%s' is out of date (tags for %d triangles, mesh has %d); "
                             "tessellate again" % (tm.Label, len(face_node), len(F)))

    nodes_by_name = {objects.model_name(n): n for n in objects.members(analysis, objects.ThermalNode)}
    mats_by_name = {objects.model_name(m): m for m in objects.members(analysis, objects.ThermalMaterial)}
    for name in tm.NodeNames:
        if name not in nodes_by_name:
            raise ThermoDecError("ThermalMesh refers to node '%s' which is no longer in the analysis; "
                                 "tessellate again" % name)
    if len(set(tm.NodeNames)) != len(tm.NodeNames):
        raise ThermoDecError("two thermal nodes share a label; node labels must be unique")

    materials = {}
    sources = {}
    for name in tm.MaterialNames:
        if name not in mats_by_name:
            raise ThermoDecError("ThermalMesh refers to material '%s' which is no longer in the "
                                 "analysis; tessellate again" % name)
        m = mats_by_name[name]
        materials[name] = {"absorptivity": m.Absorptivity, "emissivity": m.Emissivity}
        if m.Source:
            sources[name] = m.Source

    default = analysis.DefaultMaterial
    if default is not None:
        dname = objects.model_name(default)
        materials.setdefault(dname, {"absorptivity": default.Absorptivity,
                                     "emissivity": default.Emissivity})
    else:
        dname = tm.MaterialNames[0]

    nodes = {}
    for name in tm.NodeNames:
        n = nodes_by_name[name]
        entry = {"capacitance": n.Capacitance, "power": n.Power}
        if n.Material is not None:
            mname = objects.model_name(n.Material)
            materials.setdefault(mname, {"absorptivity": n.Material.Absorptivity,
                                         "emissivity": n.Material.Emissivity})
            entry["material"] = mname
        if n.IsBoundary:
            entry["fixed_temperature"] = n.FixedTemperature
        if n.BackMaterial is not None:
            bname = objects.model_name(n.BackMaterial)
            materials.setdefault(bname, {"absorptivity": n.BackMaterial.Absorptivity,
                                         "emissivity": n.BackMaterial.Emissivity})
            entry["back_material"] = bname
        elif n.TwoSided:
            entry["two_sided"] = True
        if n.Capacitance < 0:
            raise ThermoDecError("node '%s': negative capacitance %g J/K" % (n.Label, n.Capacitance))
        nodes[name] = model_file.merge_into(n, entry)

    _refuse_arithmetic_nodes(analysis, nodes_by_name, nodes)
    conductances = []
    for c in objects.members(analysis, objects.Conductance):
        if c.NodeA is None or c.NodeB is None:
            raise ThermoDecError("conductance '%s' needs two nodes" % c.Label)
        a, b = objects.model_name(c.NodeA), objects.model_name(c.NodeB)
        for end in (a, b):
            if end not in nodes:
                raise ThermoDecError("conductance '%s': node '%s' has no face in the mesh" % (c.Label, end))
        conductances.append(model_file.merge_into(c, {"from": a, "to": b, "value": c.Value}))

    for name, entry in materials.items():  # keys of an opened model file the workbench does not edit
        if name in mats_by_name:
            model_file.merge_into(mats_by_name[name], entry)
    data = {"mesh": mesh_file, "unit_scale": 1.0, "materials": materials, "default_material": dname,
            "nodes": nodes, "conductances": conductances}
    if sources:  # provenance of the coating values; top-level '_' keys are comments to the core
        data["_material_sources"] = sources
    envs = objects.members(analysis, objects.Environment)
    if len(envs) > 1:
        raise ThermoDecError("analysis '%s' has %d environments; keep one" % (analysis.Label, len(envs)))
    if envs:
        data["environment"] = model_file.merge_into(envs[0], _environment(envs[0]))
    data["analysis"] = {"type": analysis.AnalysisType}
    if analysis.AnalysisType == "transient_orbit":
        data["analysis"].update(steps_per_orbit=analysis.StepsPerOrbit, orbits=analysis.Orbits)
    model_file.merge_into(analysis, data["analysis"], "analysis.")
    data["radiation"] = model_file.merge_into(analysis, {"rays_per_face": analysis.RaysPerFace, "seed": analysis.Seed},
                                              "radiation.")
    model_file.merge_into(analysis, data)  # top-level keys: node_map, description, certificate, ...

    # Reindex materials to the order of the JSON (node default materials may have been added).
    order = list(materials)
    mat_map = np.array([order.index(n) for n in tm.MaterialNames], dtype=np.int64)
    return data, units.points_m(V_mm), F, face_node, mat_map[face_material]


def _refuse_arithmetic_nodes(analysis, nodes_by_name, entries):
    """In a transient orbit, a node of capacitance 0 J/K stores no heat: it follows the sun at
    once (a face falls to a few kelvin in eclipse). Refused unless AllowArithmeticNodes."""
    if analysis.AnalysisType != "transient_orbit" or analysis.AllowArithmeticNodes:
        return
    zero = [name for name, e in entries.items() if e["capacitance"] == 0 and "fixed_temperature" not in e]
    if zero:
        raise ThermoDecError(
            "transient_orbit: node(s) %s have capacitance 0 J/K (no heat storage: in eclipse such a "
            "face falls towards 3 K); give them a Capacitance [J/K] (automatic nodes get face area x "
            "%.4g J/(m^2 K)) or set the analysis' AllowArithmeticNodes"
            % (", ".join("'%s'" % nodes_by_name[n].Label for n in zero[:8]) + (" ..." if len(zero) > 8 else ""),
               analysis.PanelArealHeatCapacity))


def _atomic_write(path, text):
    atomic_write_text(path, text)


def core_mesh(V_m, F, face_node, face_material, node_names, material_names):
    """thermodec.Mesh of the export arrays (one-sided faces: every part is a closed solid)."""
    td = core.module()
    mesh = td.Mesh(V_m, F)
    mesh.face_node = face_node
    mesh.face_material = face_material
    mesh.node_names = list(node_names)
    mesh.material_names = list(material_names)
    return mesh


def write_model(analysis, json_path, mesh_path=None):
    """Writes model.json and its OBJ mesh (default: same name, .obj) atomically.
    Never overwrites a file the analysis reads. Returns (json_path, mesh_path)."""
    json_path = os.path.abspath(json_path)
    if mesh_path is None:
        mesh_path = os.path.splitext(json_path)[0] + ".obj"
    mesh_path = os.path.abspath(mesh_path)
    if json_path == mesh_path:
        raise ThermoDecError("model and mesh paths are the same: %s" % json_path)
    os.makedirs(os.path.dirname(json_path), exist_ok=True)
    analysis.Document.recompute()  # edits pending in the tree count before this export, not after
    rel = os.path.relpath(mesh_path, os.path.dirname(json_path))
    data, V, F, face_node, face_material = model_data(analysis, rel)
    node_names = list(data["nodes"])
    material_names = list(data["materials"])
    mesh = core_mesh(V, F, face_node, face_material, node_names, material_names)
    core.module().write_mesh(mesh_path, mesh)  # atomic, the core's own OBJ writer
    _atomic_write(json_path, json.dumps(data, indent=2) + "\n")
    analysis.ModelFile = json_path
    return json_path, mesh_path


def default_paths(analysis):
    """model.json and model.obj in OutputDirectory, else beside the document, else in the cwd."""
    folder = analysis.OutputDirectory
    if not folder:
        doc_file = analysis.Document.FileName
        folder = os.path.join(os.path.dirname(doc_file) if doc_file else os.getcwd(),
                              "%s_thermodec" % analysis.Document.Name)
    return os.path.join(folder, "model.json"), os.path.join(folder, "model.obj")
