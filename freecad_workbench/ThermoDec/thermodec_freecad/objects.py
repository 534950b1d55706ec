"""Document objects of the ThermoDec workbench (FeaturePython, persisted in .FCStd).

No GUI import here: every factory works headless and attaches a view provider only when
FreeCAD.GuiUp. Thermal quantities are SI floats (the tooltip names the unit); lengths and
angles are FreeCAD quantities converted in units.py.
"""

import re

import FreeCAD

from . import coatings, defaults, references, units
from .errors import ThermoDecError

CUSTOM = "custom"


def _add(obj, kind, name, group, tooltip, value=None):
    if name not in obj.PropertiesList:
        obj.addProperty(kind, name, group, tooltip)
        if value is not None:
            setattr(obj, name, value)


class _Proxy:
    Type = ""

    def __init__(self, obj):
        obj.Proxy = self
        self.Type = type(self).Type
        self.setup(obj)

    def setup(self, obj):
        pass

    #: Properties whose change leaves the analysis' results current (outputs, bookkeeping).
    NOT_INPUTS = {"Proxy", "Label2", "ExpressionEngine", "Visibility", "Group", "ThermalMesh", "ModelFile",
                  "ResultFile", "ReducedModelFile", "OutputDirectory", "ReferenceSignatures", "Note",
                  "ToleranceK", "ReductionStrategy", "GlobalRatio", "LoadCases", "MergeNodes",
                  "KeptModelKeys", "DefaultedModelKeys", "MergedFrom"}

    def onDocumentRestored(self, obj):
        self.setup(obj)  # adds properties introduced by newer versions

    def onChanged(self, obj, prop):
        if prop not in self.NOT_INPUTS and not prop.startswith("_") and not obj.Document.Restoring \
                and "Restore" not in obj.State:
            stale(find_analysis(obj) if not is_type(obj, ThermalAnalysis) else obj,
                  "%s of '%s' changed" % (prop, obj.Label))

    def execute(self, obj):
        pass

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps = __getstate__
    loads = __setstate__


class ThermalAnalysis(_Proxy):
    Type = "ThermoDec::ThermalAnalysis"

    def onChanged(self, obj, prop):
        if prop == "Group":  # a node, material, link or environment added or removed
            inputs = tuple(sorted(o.Name for o in getattr(obj, "Group", []) if _is_input(o)))
            known = getattr(self, "_inputs", None)
            self._inputs = inputs
            if known is not None and known != inputs and not obj.Document.Restoring:
                stale(obj, "the analysis' nodes, materials, links or environment changed")
            return
        _Proxy.onChanged(self, obj, prop)

    def setup(self, obj):
        g = "Tessellation"
        _add(obj, "App::PropertyLength", "MaxEdgeLength", g,
             "Longest triangle edge of the dense mesh", "100 mm")
        g = "Model"
        _add(obj, "App::PropertyLink", "DefaultMaterial", g,
             "Material of nodes that have none")
        _add(obj, "App::PropertyEnumeration", "AnalysisType", g, "steady or transient_orbit")
        if not obj.getEnumerationsOfProperty("AnalysisType"):
            obj.AnalysisType = ["steady", "transient_orbit"]
        _add(obj, "App::PropertyInteger", "StepsPerOrbit", g, "transient_orbit: time steps per orbit", 72)
        _add(obj, "App::PropertyInteger", "Orbits", g, "transient_orbit: max orbits to periodicity", 3)
        _add(obj, "App::PropertyInteger", "RaysPerFace", g, "Monte Carlo rays per face", 4000)
        _add(obj, "App::PropertyInteger", "Seed", g, "Monte Carlo seed", 1)
        _add(obj, "App::PropertyBool", "AllowArithmeticNodes", g,
             "transient_orbit: accept nodes of capacitance 0 J/K (no heat storage); refused otherwise", False)
        g = "Automatic nodes"
        _add(obj, "App::PropertyFloat", "PanelArealHeatCapacity", g,
             "Heat capacity per face area given to automatic nodes [J/(m^2 K)] (default: "
             + defaults.PANEL_NAME + ")", defaults.areal_heat_capacity_J_per_m2K())
        _add(obj, "App::PropertyFloat", "PanelSheetConductance", g,
             "In-plane conductance k*t of that panel [W/K]: links faces of one solid sharing an edge, "
             "G = k*t * edge length / (centroid-to-edge distances)", defaults.sheet_conductance_W_per_K())
        g = "Reduction"
        _add(obj, "App::PropertyFloat", "ToleranceK", g,
             "Reduce: max temperature difference allowed vs the dense model [K]", 0.5)
        _add(obj, "App::PropertyEnumeration", "ReductionStrategy", g, "informed (the paper's) or uniform")
        if not obj.getEnumerationsOfProperty("ReductionStrategy"):
            obj.ReductionStrategy = ["informed", "uniform"]
        _add(obj, "App::PropertyBool", "MergeNodes", g,
             "Reduce: also merge thermal nodes into isothermal nodes (thermodec reduce --merge-nodes); "
             "the reduced model.json carries the node map", False)
        _add(obj, "App::PropertyFloat", "GlobalRatio", g,
             "Decimate: fraction of the dense mesh's faces to remove (0.9 keeps 10 %)", 0.8)
        g = "Output"
        _add(obj, "App::PropertyLink", "ThermalMesh", g, "Dense tagged mesh made by Tessellate")
        _add(obj, "App::PropertyPath", "OutputDirectory", g,
             "Folder for model.json, the mesh and results (empty: beside the document)")
        _add(obj, "App::PropertyFile", "ModelFile", g, "Last exported model.json")
        _add(obj, "App::PropertyFile", "ResultFile", g, "Last simulation result.json")
        _add(obj, "App::PropertyFile", "ReducedModelFile", g,
             "Last reduced model.json (Reduce); Export for other tools writes it when current")
        g = "Reduction"
        _add(obj, "App::PropertyStringList", "LoadCases", g,
             "Reduce: load case files the reduced model must also meet (thermodec reduce --case)")


class ThermalNode(_Proxy):
    Type = "ThermoDec::ThermalNode"

    def setup(self, obj):
        g = "Geometry"
        _add(obj, "App::PropertyLinkSubList", "References", g,
             "Faces (ObjectName.FaceN) or whole shapes this node covers")
        _add(obj, "App::PropertyStringList", "ReferenceSignatures", g,
             "Centre and area of each referenced face, to re-find it after a recompute")
        obj.setEditorMode("ReferenceSignatures", 1)
        g = "Thermal"
        _add(obj, "App::PropertyLink", "Material", g, "Coating of the node's faces")
        _add(obj, "App::PropertyFloat", "Capacitance", g, "Heat capacity [J/K]; 0 = arithmetic node", 0.0)
        _add(obj, "App::PropertyFloat", "Power", g, "Internal dissipation [W]", 0.0)
        _add(obj, "App::PropertyBool", "IsBoundary", g, "Held at FixedTemperature", False)
        _add(obj, "App::PropertyFloat", "FixedTemperature", g, "Boundary temperature [K]", 293.15)
        _add(obj, "App::PropertyBool", "TwoSided", g,
             "Thin sheet radiating from both faces (not part of a closed solid)", False)
        _add(obj, "App::PropertyLink", "BackMaterial", g, "Coating of the back side (implies TwoSided)")
        _add(obj, "App::PropertyString", "Note", g, "Where the capacitance comes from (automatic nodes)")

    def onChanged(self, obj, prop):
        if prop == "References" and "ReferenceSignatures" in obj.PropertiesList:
            references.store_signatures(obj)
        _Proxy.onChanged(self, obj, prop)

    def execute(self, obj):
        _recheck(obj)


def _recheck(obj):
    """Runs on recompute after a referenced shape changed: repairs renumbered faces at once
    (warnings say which) and marks the object in error when a face is gone."""
    for message in references.check(obj):
        FreeCAD.Console.PrintWarning("ThermoDec: %s\n" % message)


class ThermalMaterial(_Proxy):
    Type = "ThermoDec::ThermalMaterial"

    def setup(self, obj):
        g = "Optical"
        _add(obj, "App::PropertyEnumeration", "Coating", g, "Library coating, or custom values")
        if not obj.getEnumerationsOfProperty("Coating"):
            obj.Coating = [CUSTOM] + coatings.coating_names()
        _add(obj, "App::PropertyFloat", "Absorptivity", g, "Solar absorptivity alpha in (0, 1]", 0.5)
        _add(obj, "App::PropertyFloat", "Emissivity", g, "IR hemispherical emissivity epsilon in (0, 1]", 0.5)
        _add(obj, "App::PropertyString", "Source", g, "Where the values come from")
        _add(obj, "App::PropertyFile", "MaterialCard", g,
             "Optional .FCMat card with SolarAbsorptivity and Emissivity keys")
        g = "Geometry"
        _add(obj, "App::PropertyLinkSubList", "References", g,
             "Faces that take this material whatever their node's material (multi-material nodes)")
        _add(obj, "App::PropertyStringList", "ReferenceSignatures", g,
             "Centre and area of each referenced face")
        obj.setEditorMode("ReferenceSignatures", 1)

    def onChanged(self, obj, prop):
        if prop == "Coating" and obj.Coating != CUSTOM:
            a, e, source = coatings.coating(obj.Coating)
            obj.Absorptivity, obj.Emissivity, obj.Source = a, e, source
        elif prop == "MaterialCard" and obj.MaterialCard:
            obj.Absorptivity, obj.Emissivity = coatings.read_fcmat(obj.MaterialCard)
            obj.Source = obj.MaterialCard
        elif prop == "References" and "ReferenceSignatures" in obj.PropertiesList:
            references.store_signatures(obj)
        _Proxy.onChanged(self, obj, prop)

    def execute(self, obj):
        _recheck(obj)


class Conductance(_Proxy):
    Type = "ThermoDec::Conductance"

    def setup(self, obj):
        g = "Thermal"
        _add(obj, "App::PropertyLink", "NodeA", g, "First node")
        _add(obj, "App::PropertyLink", "NodeB", g, "Second node")
        _add(obj, "App::PropertyFloat", "Value", g, "Conductance GL [W/K]", 0.0)
        _add(obj, "App::PropertyString", "Note", g, "Where the value comes from (automatic links)")


class Environment(_Proxy):
    Type = "ThermoDec::Environment"

    def setup(self, obj):
        g = "Environment"
        _add(obj, "App::PropertyEnumeration", "EnvironmentType", g, "orbit or fixed_sun")
        if not obj.getEnumerationsOfProperty("EnvironmentType"):
            obj.EnvironmentType = ["orbit", "fixed_sun"]
        _add(obj, "App::PropertyVector", "SunDirection", g, "fixed_sun: towards the sun, body axes",
             FreeCAD.Vector(1, 0, 0))
        _add(obj, "App::PropertyFloat", "SolarFlux", g, "fixed_sun: solar flux [W/m^2]", 1361.0)
        g = "Orbit"
        _add(obj, "App::PropertyLength", "Altitude", g, "Circular orbit altitude", "500 km")
        _add(obj, "App::PropertyAngle", "Inclination", g, "Orbit inclination", 51.6)
        _add(obj, "App::PropertyAngle", "RAAN", g, "Right ascension of the ascending node", 0.0)
        _add(obj, "App::PropertyInteger", "DayOfYear", g, "Day of year 1..366 (sun position)", 80)
        _add(obj, "App::PropertyEnumeration", "Attitude", g, "nadir, sun or inertial pointing")
        if not obj.getEnumerationsOfProperty("Attitude"):
            obj.Attitude = ["nadir", "sun", "inertial"]
        _add(obj, "App::PropertyFloat", "Albedo", g, "Earth albedo coefficient", 0.30)
        _add(obj, "App::PropertyFloat", "EarthIRFlux", g, "Earth IR flux [W/m^2]", 237.0)


# ---------------------------------------------------------------------------------------------
# Helpers and factories (headless; GUI parts only if FreeCAD.GuiUp)

def is_type(obj, proxy_class):
    return obj is not None and getattr(getattr(obj, "Proxy", None), "Type", None) == proxy_class.Type


def _is_input(obj):
    return any(is_type(obj, c) for c in (ThermalNode, ThermalMaterial, Conductance, Environment))


def stale(analysis, reason):
    """Marks the analysis' simulated results stale (thermal_result.mark_stale)."""
    if analysis is None or "Group" not in analysis.PropertiesList:
        return
    from . import model_file, thermal_result
    model_file.drop_certificate(analysis, reason)
    changed = False
    for obj in analysis.Group:
        if is_type(obj, thermal_result.ThermalResult) and "Stale" in obj.PropertiesList:
            changed = thermal_result.mark_stale(obj, reason) or changed
    if changed and FreeCAD.GuiUp:  # the plot dock's titles say "(stale)" too
        from . import plots
        dock = plots._current
        if dock is not None and dock.analysis == analysis:
            try:
                dock.refresh()
            except Exception:  # a closed dock or document: nothing to redraw
                pass


def _view(obj, icon):
    if FreeCAD.GuiUp:
        from . import viewproviders
        viewproviders.ViewProvider(obj.ViewObject, icon)


def _add_to(analysis, obj):
    if analysis is not None:
        analysis.addObject(obj)
    return obj


def model_name(obj):
    """Name of a node or material in the thermodec model: its label, spaces -> '_'."""
    return re.sub(r"\s+", "_", obj.Label.strip())


def find_analysis(obj):
    for parent in obj.InList:
        if is_type(parent, ThermalAnalysis):
            return parent
    return None


def members(analysis, proxy_class):
    return [o for o in analysis.Group if is_type(o, proxy_class)]


def import_step(doc, path, name=None):
    """Loads a STEP file into one Part::Feature with Part.read (on FreeCAD 0.20, Import.insert
    crashes on some STEP files). Raises ThermoDecError when the file gives no face."""
    import os
    import Part
    try:
        shape = Part.read(path)
    except Exception as e:  # OCC reports unreadable files as a generic exception
        raise ThermoDecError("cannot read STEP file %s: %s" % (path, e)) from None
    if shape.isNull() or not shape.Faces:
        raise ThermoDecError("STEP file %s has no faces" % path)
    label = name or os.path.splitext(os.path.basename(path))[0]
    obj = doc.addObject("Part::Feature", re.sub(r"\W", "_", label) or "Step")
    obj.Label = label
    obj.Shape = shape
    return obj


def makeAnalysis(doc, name="ThermalAnalysis"):
    obj = doc.addObject("App::DocumentObjectGroupPython", name)
    ThermalAnalysis(obj)
    _view(obj, "Analysis.svg")
    return obj


def makeNode(analysis, refs=(), name="Node", material=None, capacitance=0.0, power=0.0,
             fixed_temperature=None):
    """A thermal node over `refs`: [(obj, ["Face1", ...])] or [(obj, "")] for a whole shape.
    capacitance [J/K], power [W], fixed_temperature [K] or None."""
    doc = analysis.Document
    obj = doc.addObject("App::FeaturePython", name)
    ThermalNode(obj)
    obj.References = references.normalise(refs)
    obj.Material = material
    obj.Capacitance = float(capacitance)
    obj.Power = float(power)
    if fixed_temperature is not None:
        obj.IsBoundary = True
        obj.FixedTemperature = float(fixed_temperature)
    _view(obj, "Node.svg")
    return _add_to(analysis, obj)


def makeMaterial(analysis, coating=None, name=None, absorptivity=None, emissivity=None,
                 refs=(), card=None):
    """A material from the coating library (`coating`), custom values, or an .FCMat card."""
    doc = analysis.Document
    obj = doc.addObject("App::FeaturePython", name or coating or "Material")
    ThermalMaterial(obj)
    if coating:
        obj.Coating = coating
    if card:
        obj.MaterialCard = card
    if absorptivity is not None:
        obj.Absorptivity = float(absorptivity)
    if emissivity is not None:
        obj.Emissivity = float(emissivity)
    obj.References = references.normalise(refs)
    _view(obj, "Material.svg")
    return _add_to(analysis, obj)


def makeConductance(analysis, node_a, node_b, value, name="Conductance"):
    """Conductive link between two ThermalNodes, value [W/K]."""
    obj = analysis.Document.addObject("App::FeaturePython", name)
    Conductance(obj)
    obj.NodeA, obj.NodeB, obj.Value = node_a, node_b, float(value)
    _view(obj, "Conductance.svg")
    return _add_to(analysis, obj)


def makeEnvironment(analysis, environment_type="orbit", name="Environment", **values):
    """Environment; keyword values set the properties (SolarFlux=..., Altitude='600 km', ...)."""
    obj = analysis.Document.addObject("App::FeaturePython", name)
    Environment(obj)
    obj.EnvironmentType = environment_type
    for key, value in values.items():
        setattr(obj, key, value)
    _view(obj, "Environment.svg")
    return _add_to(analysis, obj)


def assign_material(material, refs):
    """Adds faces to a material's per-face overrides."""
    current = list(material.References)
    material.References = current + references.normalise(refs)


def _solid_groups(shape):
    """[[face index, ...] per solid] of a shape (shells, or the whole shape, when it has no solid)."""
    index = {}
    for i, f in enumerate(shape.Faces):
        index.setdefault(f.hashCode(), []).append(i)

    def find(face):
        return next(i for i in index.get(face.hashCode(), []) if shape.Faces[i].isSame(face))
    parts = shape.Solids or shape.Shells or [shape]
    return [[find(f) for f in part.Faces] for part in parts]


def _shared_edges(shape, faces):
    """{(i, j): [edge, ...]} for faces i < j of `faces` (indices into shape.Faces) sharing an edge."""
    by_edge = {}
    for i in faces:
        for e in shape.Faces[i].Edges:
            by_edge.setdefault(e.hashCode(), []).append((i, e))
    pairs = {}
    for entries in by_edge.values():
        for a in range(len(entries)):
            for b in range(a + 1, len(entries)):
                (i, e), (j, f) = entries[a], entries[b]
                if i != j and e.isSame(f):
                    pairs.setdefault((min(i, j), max(i, j)), []).append(e)
    return pairs


def _edge_links(analysis, shape_obj, node_of_face, sheet_W_per_K):
    """Conductances between nodes of faces of one solid that share an edge (defaults.py)."""
    import Part
    shape = shape_obj.Shape
    links = []
    for faces in _solid_groups(shape):
        for (i, j), edges in sorted(_shared_edges(shape, faces).items()):
            a, b = node_of_face[i], node_of_face[j]
            if a == b:
                continue
            value = 0.0
            for e in edges:
                mid = Part.Vertex(e.valueAt(0.5 * (e.FirstParameter + e.LastParameter)))
                d = [units.length_m(mid.distToShape(Part.Vertex(shape.Faces[k].CenterOfMass))[0]) for k in (i, j)]
                value += defaults.edge_conductance_W_per_K(sheet_W_per_K, units.length_m(e.Length), d[0], d[1])
            link = makeConductance(analysis, a, b, value, name="link_%s_%s" % (a.Name, b.Name))
            link.Label = "link_%s_%s" % (model_name(a), model_name(b))
            link.Note = "default: panel k*t %.4g W/K x %.4g m shared edge / centroid-to-edge path" % (
                sheet_W_per_K, sum(units.length_m(e.Length) for e in edges))
            links.append(link)
    return links


def automatic_nodes(analysis, shapes, per="face", material=None, physical_defaults=True):
    """One ThermalNode per B-rep face or per solid of each shape object.

    With physical_defaults (docs/freecad.md, "Automatic nodes"), each node's capacitance is its
    area x the analysis' PanelArealHeatCapacity [J/(m^2 K)] (every face a default honeycomb
    panel) and, per face, faces of one solid sharing an edge are linked by a Conductance of
    PanelSheetConductance x edge length / centroid-to-edge path [W/K]; the report view says so.
    Returns the new nodes. Raises ThermoDecError for an empty shape."""
    if per not in ("face", "solid"):
        raise ThermoDecError("automatic nodes: per must be 'face' or 'solid', not '%s'" % per)
    nodes = []
    for shape_obj in shapes:
        shape = getattr(shape_obj, "Shape", None)
        if shape is None or shape.isNull() or not shape.Faces:
            raise ThermoDecError("automatic nodes: '%s' has no faces" % shape_obj.Label)
        if per == "face":
            groups = [("Face%d" % (i + 1), [i]) for i in range(len(shape.Faces))]
        else:
            groups = [("Solid%d" % (k + 1), faces) for k, faces in enumerate(_solid_groups(shape))]
        made, node_of_face = [], {}
        for suffix, faces in groups:
            node = makeNode(analysis, [(shape_obj, ["Face%d" % (i + 1) for i in faces])],
                            name="%s_%s" % (shape_obj.Name, suffix), material=material)
            node.Label = "%s_%s" % (model_name(shape_obj), suffix)
            if physical_defaults:
                area = sum(units.area_m2(shape.Faces[i].Area) for i in faces)
                node.Capacitance = defaults.face_capacitance_J_per_K(area, analysis.PanelArealHeatCapacity)
                node.Note = "default: %.4g m^2 x %.4g J/(m^2 K) panel" % (area, analysis.PanelArealHeatCapacity)
            for i in faces:
                node_of_face[i] = node
            made.append(node)
        links = _edge_links(analysis, shape_obj, node_of_face, analysis.PanelSheetConductance) \
            if physical_defaults and per == "face" else []
        if physical_defaults:
            FreeCAD.Console.PrintMessage(
                "ThermoDec: %d automatic node(s) on '%s': capacitance = face area x %.4g J/(m^2 K) "
                "(%.4g .. %.4g J/K; default panel: %s); %d conductive link(s) between faces of one solid "
                "sharing an edge, k*t %.4g W/K x edge length / centroid-to-edge path (%.4g .. %.4g W/K). "
                "Edit a node's Capacitance or a link's Value when the design is known.\n" % (
                    len(made), shape_obj.Label, analysis.PanelArealHeatCapacity,
                    min(n.Capacitance for n in made), max(n.Capacitance for n in made), defaults.PANEL_NAME,
                    len(links), analysis.PanelSheetConductance,
                    min([c.Value for c in links] or [0.0]), max([c.Value for c in links] or [0.0])))
        nodes += made
    return nodes


# ---------------------------------------------------------------------------------------------
# Saving: an analysis without OutputDirectory writes beside its document (export.default_paths),
# so saving the document somewhere new moves that folder. Its files follow, and the analysis'
# and results' file paths are rewritten before the document is written.

_PATH_PROPERTIES = ("ModelFile", "ResultFile", "ReducedModelFile")


def follow_save(doc, filename):
    """Copies each default-output analysis' folder to the one beside `filename` and points its
    file properties there. Returns the folders copied [(old, new)]."""
    import os
    import shutil
    moved = []
    new = os.path.join(os.path.dirname(os.path.abspath(filename)), "%s_thermodec" % doc.Name)
    for analysis in [o for o in doc.Objects if is_type(o, ThermalAnalysis)]:
        if analysis.OutputDirectory or not analysis.ModelFile:
            continue
        old = os.path.dirname(analysis.ModelFile)
        if os.path.normpath(old) == os.path.normpath(new) or not os.path.isdir(old):
            continue
        shutil.copytree(old, new, dirs_exist_ok=True)
        holders = [analysis] + [o for o in analysis.Group if "ResultFile" in o.PropertiesList]
        for obj in holders:
            for prop in _PATH_PROPERTIES:
                path = getattr(obj, prop, "") if prop in obj.PropertiesList else ""
                if path and os.path.normpath(path).startswith(os.path.normpath(old) + os.sep):
                    setattr(obj, prop, os.path.join(new, os.path.relpath(path, old)))
        FreeCAD.Console.PrintMessage("ThermoDec: outputs of '%s' copied to %s (the document moved)\n"
                                     % (analysis.Label, new))
        moved.append((old, new))
    return moved


class SaveObserver:
    """App document observer (registered by Init.py): follow_save before every save."""

    def slotStartSaveDocument(self, doc, filename):
        try:
            follow_save(doc, filename)
        except Exception as e:  # never block a save
            FreeCAD.Console.PrintError("ThermoDec: outputs not moved with the document: %s\n" % e)
