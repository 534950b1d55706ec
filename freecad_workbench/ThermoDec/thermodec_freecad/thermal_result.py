"""ThermalResult: a simulation's node temperatures over the orbit, shown on a result mesh
(the analysis' ThermalMesh or an imported / reduced mesh). No GUI import here: the object
keeps the whole time series, so choosing what the mesh shows (min, mean or max over the
orbit, or one time step) is a property change and a recompute, headless or in the GUI, and
undoable like any other edit. The view provider (viewproviders.py) draws the colour bar."""

import numpy as np

import FreeCAD

from . import objects, temperature_field
from .errors import ThermoDecError

FIELDS = list(temperature_field.STATISTICS) + ["time step"]

#: Prop_Output: setting it does not touch the mesh, so showing a field never asks the mesh
#: (and the result depending on it) to recompute again.
_OUTPUT = 8


class ThermalResult(objects._Proxy):
    Type = "ThermoDec::ThermalResult"

    def setup(self, obj):
        g = "Result"
        objects._add(obj, "App::PropertyLink", "ResultMesh", g, "Mesh feature the temperatures colour")
        objects._add(obj, "App::PropertyFile", "ResultFile", g, "result.json the numbers came from")
        objects._add(obj, "App::PropertyStringList", "NodeNames", g, "Nodes, in the order of the rows")
        objects._add(obj, "App::PropertyFloatList", "TimesS", g, "Times of the samples over one orbit [s]")
        objects._add(obj, "App::PropertyFloatList", "TemperaturesK", g,
                     "Node temperatures [K], node after node, one value per time")
        objects._add(obj, "App::PropertyInteger", "Seed", g, "Monte Carlo seed the simulation used")
        objects._add(obj, "App::PropertyInteger", "RaysPerFace", g, "Rays per face the simulation used")
        objects._add(obj, "App::PropertyBool", "TracksAnalysis", g,
                     "Simulated from the analysis' inputs (goes stale when they change)", False)
        objects._add(obj, "App::PropertyBool", "Stale", g, "An input changed since this result was computed", False)
        objects._add(obj, "App::PropertyString", "StaleReason", g, "The first input change since the result")
        for name in ("TimesS", "TemperaturesK", "Seed", "RaysPerFace", "NodeNames", "Stale", "StaleReason"):
            obj.setEditorMode(name, 1)
        obj.setEditorMode("TracksAnalysis", 2)
        g = "Display"
        objects._add(obj, "App::PropertyEnumeration", "Field", g,
                     "What the mesh shows: each node's min, mean or max over the orbit, or one time step")
        if not obj.getEnumerationsOfProperty("Field"):
            obj.Field = FIELDS
            obj.Field = "mean"
        objects._add(obj, "App::PropertyInteger", "TimeStep", g, "Time step shown when Field is 'time step'", 0)
        objects._add(obj, "App::PropertyFloat", "ColourMinK", g, "Colour bar bottom (blue) [K]")
        objects._add(obj, "App::PropertyFloat", "ColourMaxK", g, "Colour bar top (red) [K]")
        objects._add(obj, "App::PropertyString", "Shown", g, "The field shown, in words")
        for name in ("ColourMinK", "ColourMaxK", "Shown"):
            obj.setEditorMode(name, 1)

    def onChanged(self, obj, prop):
        pass  # a result is an output: showing another field leaves the others current

    def execute(self, obj):
        show(obj)


def matrix(obj):
    """(node names, times [s], temperatures #N x #S [K]) held by a ThermalResult."""
    nodes, times = list(obj.NodeNames), np.asarray(obj.TimesS, dtype=float)
    T = np.asarray(obj.TemperaturesK, dtype=float)
    if len(nodes) == 0 or len(times) == 0 or T.size != len(nodes) * len(times):
        raise ThermoDecError("result '%s' holds %d temperatures for %d nodes x %d times"
                             % (obj.Label, T.size, len(nodes), len(times)))
    return nodes, times, T.reshape(len(nodes), len(times))


def field(obj):
    """The field shown: 'min' / 'mean' / 'max', or the time step index."""
    return obj.TimeStep if obj.Field == "time step" else obj.Field


def show(obj):
    """Writes the chosen field to the result mesh: FaceTemperature [K] and FaceColors (the
    colour map between ColourMinK and ColourMaxK, the field's range over the nodes)."""
    nodes, times, T = matrix(obj)
    mesh = obj.ResultMesh
    if mesh is None:
        raise ThermoDecError("result '%s' has no mesh" % obj.Label)
    values = temperature_field.node_field(T, field(obj))
    faces = temperature_field.face_values(values, mesh.FaceNode, mesh.NodeNames, nodes)
    low, high = temperature_field.colour_range(values)
    obj.ColourMinK, obj.ColourMaxK = low, high
    obj.Shown = temperature_field.field_name(field(obj), times)
    mesh.FaceTemperature = [float(t) for t in faces]
    mesh.FaceColors = [tuple(c) for c in temperature_field.colours(faces, low, high)]


def _result_properties(mesh):
    """The mesh-side properties a result writes (added to older documents' meshes too)."""
    if "FaceColors" not in mesh.PropertiesList:
        mesh.addProperty("App::PropertyColorList", "FaceColors", "Results",
                         "Colour per triangle of the shown temperature field", _OUTPUT)
    try:
        mesh.setPropertyStatus("FaceTemperature", "Output")
    except (AttributeError, ValueError):  # older FreeCAD: the mesh then recomputes once more
        pass


def makeResult(analysis, mesh, nodes, times_s, temperatures_K, seed=None, rays_per_face=None,
               result_file="", name="ThermalResult"):
    """A ThermalResult on `mesh` (a ThermalMesh-like feature with FaceNode/NodeNames) from a
    simulation: node names, times [s] #S, temperatures [K] #N x #S; seed and rays per face as
    the simulation used them (None: unknown, shown as -1). Replaces the analysis' earlier
    result on the same mesh. Shows the mean over the orbit."""
    T = np.asarray(temperatures_K, dtype=float)
    if T.shape != (len(nodes), len(times_s)):
        raise ThermoDecError("temperatures are %s, expected %d nodes x %d times" % (T.shape, len(nodes), len(times_s)))
    doc = analysis.Document
    for old in objects.members(analysis, ThermalResult):
        if old.ResultMesh == mesh:
            doc.removeObject(old.Name)
    _result_properties(mesh)
    obj = doc.addObject("App::FeaturePython", name)
    ThermalResult(obj)
    obj.ResultMesh = mesh
    obj.ResultFile = result_file or ""
    obj.NodeNames = [str(n) for n in nodes]
    obj.TimesS = [float(t) for t in times_s]
    obj.TemperaturesK = [float(t) for t in T.reshape(-1)]
    obj.Seed = -1 if seed is None else int(seed)
    obj.RaysPerFace = -1 if rays_per_face is None else int(rays_per_face)
    if FreeCAD.GuiUp:
        from . import viewproviders
        viewproviders.ViewProviderThermalResult(obj.ViewObject)
    analysis.addObject(obj)
    show(obj)
    obj.purgeTouched()
    if FreeCAD.GuiUp:
        for other in objects.members(analysis, ThermalResult):  # one colour bar at a time
            if other != obj and other.ViewObject is not None:
                other.ViewObject.Visibility = False
        obj.ViewObject.Proxy.refresh(obj.ViewObject)
    return obj


def set_field(obj, field_value):
    """Shows 'min', 'mean', 'max' or time step k (an int) and recomputes the result."""
    if field_value in temperature_field.STATISTICS:
        obj.Field = field_value
    else:
        k = int(field_value)
        if not 0 <= k < len(obj.TimesS):
            raise ThermoDecError("time step %d outside 0..%d" % (k, len(obj.TimesS) - 1))
        obj.Field = "time step"
        obj.TimeStep = k
    obj.recompute()
    return obj


STALE_SUFFIX = " (stale)"


def mark_stale(result, reason):
    """Marks a result computed from the analysis' inputs as out of date: Stale, the reason, and
    " (stale)" after its label in the tree."""
    if result.Stale or not result.TracksAnalysis:
        return False
    result.Stale = True
    result.StaleReason = reason
    if not result.Label.endswith(STALE_SUFFIX):
        result.Label = result.Label + STALE_SUFFIX
    FreeCAD.Console.PrintWarning("ThermoDec: result '%s' is stale: %s; simulate (or reduce) again\n"
                                 % (result.Label, reason))
    return True
