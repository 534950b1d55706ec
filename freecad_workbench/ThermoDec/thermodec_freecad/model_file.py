"""A thermodec model file (docs/model-format.md) opened in FreeCAD, and written back whole.

open_model() makes an analysis of a model.json: its materials, nodes, conductances,
environment and settings as the workbench's objects, over the model's own mesh (read by the
core) as the analysis' ThermalMesh, so Simulate, Reduce and the exports run on it. The
workbench edits only some keys; every other key of the file (a node's `power_schedule_W` and
`heater`, the environment's `central_body`, the `node_map` of a merged model, ...) is kept on the
object it belongs to, read-only in its `KeptModelKeys` property (`key = JSON value`), and
export.model_data writes it back as it was. A key the file left to the core's default stays
out of the written file until its property is edited (`DefaultedModelKeys`): an Albedo shown
as 0.3 does not override a central body's own albedo.
"""

import json
import os

from . import core, merged_nodes, objects, units
from .errors import ThermoDecError

KEPT = "KeptModelKeys"
DEFAULTED = "DefaultedModelKeys"

#: Keys the workbench edits, per section; every other key is kept as it is.
NODE_KEYS = ("material", "capacitance", "power", "fixed_temperature", "back_material")
MATERIAL_KEYS = ("absorptivity", "emissivity")
CONDUCTANCE_KEYS = ("from", "to", "value")
ORBIT_KEYS = ("type", "altitude_km", "inclination_deg", "raan_deg", "day_of_year", "attitude", "albedo", "earth_ir_flux")
FIXED_SUN_KEYS = ("type", "sun_direction", "solar_flux")
TOP_KEYS = ("mesh", "unit_scale", "materials", "default_material", "nodes", "conductances", "environment",
            "analysis", "radiation", "_material_sources")


def _lines_property(obj, name, tooltip):
    if name not in obj.PropertiesList:
        obj.addProperty("App::PropertyStringList", name, "Model file", tooltip)
    obj.setEditorMode(name, 1)


def _write_lines(obj, name, entries, tooltip):
    if entries:
        _lines_property(obj, name, tooltip)
        setattr(obj, name, ["%s = %s" % (k, json.dumps(v)) for k, v in entries.items()])


def _read_lines(obj, name):
    out = {}
    for line in (getattr(obj, name) if name in obj.PropertiesList else []):
        key, _, text = line.partition(" = ")
        out[key] = json.loads(text)
    return out


def keep(obj, entries):
    """Stores the model file's `entries` ({key: value}) that the workbench does not edit on obj."""
    _write_lines(obj, KEPT, entries, "Keys of the model file the workbench does not edit: written back as they "
                                     "are (key = JSON value; read-only)")


def kept(obj):
    """{key: value} of the model file kept on obj ({} for objects made in FreeCAD)."""
    return _read_lines(obj, KEPT)


def drop_certificate(analysis, reason):
    """An opened reduced model's `certificate` (its verification against its original) holds
    for the file as it was: the first edit of an input drops it, saying why."""
    entries = kept(analysis)
    if "certificate" in entries:
        del entries["certificate"]
        setattr(analysis, KEPT, ["%s = %s" % (k, json.dumps(v)) for k, v in entries.items()])
        import FreeCAD
        FreeCAD.Console.PrintWarning("ThermoDec: the model's certificate (its verification against the original) "
                                     "is dropped: %s\n" % reason)


def _defaulted(obj, entries):
    _write_lines(obj, DEFAULTED, entries, "Keys the model file left to the core's default: not written while "
                                          "the property keeps this value (read-only)")


def merge_into(obj, entry, prefix=""):
    """Completes an exported section `entry` with the keys kept on obj (those starting with
    `prefix`, which is stripped) and drops the keys the file left out whose value is unchanged."""
    for key, value in _read_lines(obj, DEFAULTED).items():
        if key.startswith(prefix) and key[len(prefix):] in entry and _same(entry[key[len(prefix):]], value):
            del entry[key[len(prefix):]]
    for key, value in kept(obj).items():
        if key.startswith(prefix) and "." not in key[len(prefix):]:
            entry.setdefault(key[len(prefix):], value)
    if "power_schedule_W" in entry and entry.get("power") == 0:
        del entry["power"]  # a schedule replaces the constant power (the file may not give both)
    return entry


def _same(a, b):
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return abs(a - b) <= 1e-9 * max(1.0, abs(b))
    return a == b


def _absent(section, keys, written):
    """{key: value written by the export} for the keys of `keys` the file's `section` lacks."""
    return {k: written[k] for k in keys if k not in section and k in written}


def open_model(doc, path):
    """A ThermalAnalysis of the model file at `path` in `doc` (checked and read by the core
    first: a bad file is the core's one-line error). Node and material labels are the model's
    names, so `doc` must not hold other nodes or materials of those names (a new document).
    Returns the analysis."""
    td = core.module()
    path = os.path.abspath(path)
    model = td.load_model(path)
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise ThermoDecError("cannot read %s: %s" % (path, e)) from None
    stem = os.path.splitext(os.path.basename(path))[0]
    analysis = objects.makeAnalysis(doc)
    analysis.Label = "%s (%s)" % (stem, os.path.basename(os.path.dirname(path)) or stem)
    materials = _materials(analysis, model, data.get("materials", {}))
    if data.get("default_material") in materials:
        analysis.DefaultMaterial = materials[data["default_material"]]
    nodes = _nodes(analysis, model, data.get("nodes", {}), materials)
    for c in data.get("conductances", []):
        link = objects.makeConductance(analysis, nodes[c["from"]], nodes[c["to"]], c["value"], name="link")
        link.Label = "link_%s_%s" % (c["from"], c["to"])
        keep(link, {k: v for k, v in c.items() if k not in CONDUCTANCE_KEYS})
    if "environment" in data:
        _environment(analysis, data["environment"])
    _settings(analysis, data)
    if any(n.Capacitance == 0 and not n.IsBoundary for n in nodes.values()):
        analysis.AllowArithmeticNodes = True  # the file has them (the workbench refuses them only in its own set-ups)
    mesh = _mesh(analysis, model, data.get("nodes", {}), path)
    node_map = data.get("node_map", {})
    merged_nodes.show(analysis, mesh, node_map, nodes_of=nodes)
    for merged, names in merged_nodes.members_of(node_map).items():
        if merged in nodes:
            node = nodes[merged]
            node.addProperty("App::PropertyStringList", "MergedFrom", "Model file", "Original nodes merged into this one")
            node.MergedFrom = names
            node.setEditorMode("MergedFrom", 1)
    analysis.Document.recompute()
    return analysis


def _label(obj, name):
    """Labels obj with the model's name: labels are the model's names and unique in a document."""
    obj.Label = name
    if obj.Label != name:
        raise ThermoDecError("'%s' is already a label in document '%s': open the model file in a new document"
                             % (name, obj.Document.Label))


def _materials(analysis, model, section):
    out = {}
    for m in model.materials:
        mat = objects.makeMaterial(analysis, name=m.name, absorptivity=m.absorptivity, emissivity=m.emissivity)
        _label(mat, m.name)
        keep(mat, {k: v for k, v in section.get(m.name, {}).items() if k not in MATERIAL_KEYS})
        out[m.name] = mat
    return out


def _nodes(analysis, model, section, materials):
    out = {}
    for name in model.mesh.node_names:
        entry = section.get(name, {})
        node = objects.makeNode(analysis, (), name=name, material=materials.get(entry.get("material")),
                                capacitance=entry.get("capacitance", 0.0), power=entry.get("power", 0.0),
                                fixed_temperature=entry.get("fixed_temperature"))
        _label(node, name)
        if "back_material" in entry:
            node.BackMaterial = materials[entry["back_material"]]
        if entry.get("two_sided") is True:
            node.TwoSided = True
        extra = {k: v for k, v in entry.items() if k not in NODE_KEYS and not (k == "two_sided" and v is True)}
        keep(node, extra)
        _defaulted(node, _absent(entry, ("capacitance", "power"), {"capacitance": node.Capacitance, "power": node.Power}))
        out[name] = node
    return out


def _environment(analysis, section):
    from . import export
    kind = section.get("type", "orbit")
    values = {}
    if kind == "fixed_sun":
        if "sun_direction" in section:
            import FreeCAD
            values["SunDirection"] = FreeCAD.Vector(*section["sun_direction"])
        if "solar_flux" in section:
            values["SolarFlux"] = float(section["solar_flux"])
        known = FIXED_SUN_KEYS
    else:
        props = {"altitude_km": ("Altitude", lambda v: "%r km" % float(v)), "inclination_deg": ("Inclination", float),
                 "raan_deg": ("RAAN", float), "day_of_year": ("DayOfYear", int), "attitude": ("Attitude", str),
                 "albedo": ("Albedo", float), "earth_ir_flux": ("EarthIRFlux", float)}
        values = {props[k][0]: props[k][1](v) for k, v in section.items() if k in props}
        known = ORBIT_KEYS
    env = objects.makeEnvironment(analysis, kind, **values)
    keep(env, {k: v for k, v in section.items() if k not in known})
    _defaulted(env, _absent(section, known, export._environment(env)))
    return env


def _settings(analysis, data):
    a = data.get("analysis", {})
    if "type" in a:
        analysis.AnalysisType = a["type"]
    if "steps_per_orbit" in a:
        analysis.StepsPerOrbit = int(a["steps_per_orbit"])
    if "orbits" in a:
        analysis.Orbits = int(a["orbits"])
    r = data.get("radiation", {})
    if "rays_per_face" in r:
        analysis.RaysPerFace = int(r["rays_per_face"])
    if "seed" in r:
        analysis.Seed = int(r["seed"])
    extra = {k: v for k, v in data.items() if k not in TOP_KEYS}
    extra.update({"analysis." + k: v for k, v in a.items() if k not in ("type", "steps_per_orbit", "orbits")})
    extra.update({"radiation." + k: v for k, v in r.items() if k not in ("rays_per_face", "seed")})
    keep(analysis, extra)
    absent = {}
    if a.get("type") == "transient_orbit":
        absent.update({"analysis." + k: v for k, v in (("steps_per_orbit", analysis.StepsPerOrbit),
                                                         ("orbits", analysis.Orbits)) if k not in a})
    absent.update({"radiation." + k: v for k, v in (("rays_per_face", analysis.RaysPerFace), ("seed", analysis.Seed))
                   if k not in r})
    _defaulted(analysis, absent)


def _mesh(analysis, model, section, path):
    """The model's mesh as the analysis' ThermalMesh; faces without a front material (-1: the
    node's) take their node's, else the default material."""
    import numpy as np
    from . import results
    feature, _ = results._mesh_feature(analysis, model.mesh, path, None, "ThermalMesh")
    names = list(feature.MaterialNames)
    face_material = np.asarray(model.mesh.face_material)
    if np.any(face_material < 0):
        node_names = list(feature.NodeNames)
        default_name = model.materials[model.default_material].name if 0 <= model.default_material < len(model.materials) else ""
        default = names.index(default_name) if default_name in names else 0
        per_node = [names.index(section.get(n, {}).get("material")) if section.get(n, {}).get("material") in names
                    else default for n in node_names]
        face_node = np.asarray(model.mesh.face_node)
        feature.FaceMaterial = [int(m) if m >= 0 else per_node[int(face_node[f])] for f, m in enumerate(face_material)]
    analysis.ThermalMesh = feature
    return feature
