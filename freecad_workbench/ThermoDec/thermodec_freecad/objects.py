"""Document objects of the ThermoDec workbench (FeaturePython, persisted in .FCStd).

No GUI import here: every factory works headless and attaches a view provider only when
FreeCAD.GuiUp. Thermal quantities are SI floats (the tooltip names the unit); lengths and
angles are FreeCAD quantities converted in units.py.
"""

import re

import FreeCAD

from . import coatings, references
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

    def onDocumentRestored(self, obj):
        self.setup(obj)  # adds properties introduced by newer versions

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
        g = "Reduction"
        _add(obj, "App::PropertyFloat", "ToleranceK", g,
             "Reduce: max temperature difference allowed vs the dense model [K]", 0.5)
        _add(obj, "App::PropertyEnumeration", "ReductionStrategy", g, "informed (the paper's) or uniform")
        if not obj.getEnumerationsOfProperty("ReductionStrategy"):
            obj.ReductionStrategy = ["informed", "uniform"]
        _add(obj, "App::PropertyFloat", "GlobalRatio", g,
             "Decimate: fraction of the dense mesh's faces to remove (0.9 keeps 10 %)", 0.8)
        g = "Output"
        _add(obj, "App::PropertyLink", "ThermalMesh", g, "Dense tagged mesh made by Tessellate")
        _add(obj, "App::PropertyPath", "OutputDirectory", g,
             "Folder for model.json, the mesh and results (empty: beside the document)")
        _add(obj, "App::PropertyFile", "ModelFile", g, "Last exported model.json")
        _add(obj, "App::PropertyFile", "ResultFile", g, "Last simulation result.json")


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

    def onChanged(self, obj, prop):
        if prop == "References" and "ReferenceSignatures" in obj.PropertiesList:
            references.store_signatures(obj)

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

    def execute(self, obj):
        _recheck(obj)


class Conductance(_Proxy):
    Type = "ThermoDec::Conductance"

    def setup(self, obj):
        g = "Thermal"
        _add(obj, "App::PropertyLink", "NodeA", g, "First node")
        _add(obj, "App::PropertyLink", "NodeB", g, "Second node")
        _add(obj, "App::PropertyFloat", "Value", g, "Conductance GL [W/K]", 0.0)


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


def automatic_nodes(analysis, shapes, per="face", material=None):
    """One ThermalNode per B-rep face or per solid of each shape object.
    Returns the new nodes. Raises ThermoDecError for an empty shape."""
    if per not in ("face", "solid"):
        raise ThermoDecError("automatic nodes: per must be 'face' or 'solid', not '%s'" % per)
    nodes = []
    for shape_obj in shapes:
        shape = getattr(shape_obj, "Shape", None)
        if shape is None or shape.isNull() or not shape.Faces:
            raise ThermoDecError("automatic nodes: '%s' has no faces" % shape_obj.Label)
        if per == "face":
            groups = [("Face%d" % (i + 1), ["Face%d" % (i + 1)]) for i in range(len(shape.Faces))]
        else:
            solids = shape.Solids or [shape]
            groups = []
            for k, solid in enumerate(solids):
                subs = ["Face%d" % (i + 1) for i, f in enumerate(shape.Faces)
                        if any(f.isSame(g) for g in solid.Faces)]
                groups.append(("Solid%d" % (k + 1), subs))
        for suffix, subs in groups:
            nodes.append(makeNode(analysis, [(shape_obj, subs)], name="%s_%s" % (shape_obj.Name, suffix),
                                  material=material))
            nodes[-1].Label = "%s_%s" % (model_name(shape_obj), suffix)
    return nodes
