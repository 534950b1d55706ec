"""View providers (GUI only; imported when FreeCAD.GuiUp)."""

import os

import FreeCAD

ICONS = os.path.join(os.path.dirname(os.path.dirname(__file__)), "Resources", "icons")


def icon(name):
    return os.path.join(ICONS, name)


class ViewProvider:
    def __init__(self, vobj, icon_name):
        vobj.Proxy = self
        self.icon_name = icon_name

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon(getattr(self, "icon_name", "ThermoDec.svg"))

    def claimChildren(self):
        obj = getattr(self, "Object", None)
        return list(getattr(obj, "Group", [])) if obj is not None else []

    def __getstate__(self):
        return {"icon_name": getattr(self, "icon_name", "ThermoDec.svg")}

    def __setstate__(self, state):
        if state:
            self.icon_name = state.get("icon_name", "ThermoDec.svg")

    dumps = __getstate__
    loads = __setstate__

    def _panel(self, vobj):
        """The task panel that edits this object, or None (environments: EnvironmentPanel)."""
        from . import objects, taskpanels
        obj = vobj.Object
        if objects.is_type(obj, objects.Environment):
            return taskpanels.EnvironmentPanel(objects.find_analysis(obj), obj)
        return None

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        panel = self._panel(vobj)
        if panel is None:
            return None  # FreeCAD's default edit
        import FreeCADGui
        FreeCADGui.Control.showDialog(panel)
        return True

    def unsetEdit(self, vobj, mode=0):
        from . import objects
        if mode != 0 or not objects.is_type(vobj.Object, objects.Environment):
            return None
        import FreeCADGui
        FreeCADGui.Control.closeDialog()
        return True


class ViewProviderThermalMesh(ViewProvider):
    def __init__(self, vobj):
        super().__init__(vobj, "Tessellate.svg")

    def claimChildren(self):
        """The merged nodes of the mesh's model, each labelled with its members (merged_nodes.py)."""
        obj = getattr(self, "Object", None)
        return list(getattr(obj, "MergedNodes", [])) if obj is not None else []


def _palette(k):
    # Distinct, stable colours per node index (golden-ratio hue walk).
    import colorsys
    h = (k * 0.618033988749895) % 1.0
    return colorsys.hsv_to_rgb(h, 0.55, 0.95)


def _heat(t):
    from .temperature_field import heat_colour
    return heat_colour(t)


def _colour_faces(obj, colours):
    """Per-triangle colours on a Mesh feature: one segment per colour, highlighted."""
    import Mesh
    # Same facets in the same order, no earlier segments. One point triple per facet: the
    # (points, indices) form would drop facets on edges that two others already share.
    mesh = Mesh.Mesh([f.Points for f in obj.Mesh.Facets])
    groups = {}
    for f, c in enumerate(colours):
        groups.setdefault(c, []).append(f)
    keys = list(groups)
    for c in keys:
        mesh.addSegment(groups[c])
    obj.Mesh = mesh
    if obj.ViewObject is not None:
        obj.ViewObject.highlightSegments(keys)


def colour_by_node(obj):
    _colour_faces(obj, [_palette(n) for n in obj.FaceNode])


def colour_by_temperature(obj, temperatures, t_min, t_max):
    span = (t_max - t_min) or 1.0
    # Quantise to 32 levels so the number of segments stays small.
    colours = [_heat(round((t - t_min) / span * 31) / 31) for t in temperatures]
    _colour_faces(obj, colours)


def _legend_graph(low, high, title):
    """Coin scene of the colour bar, drawn over the 3D view at its right: the map's bands
    bottom (low) to top (high), labels in K and the field's name. Its own orthographic camera
    keeps it fixed on screen whatever the view."""
    from pivy import coin
    from .temperature_field import legend
    bands, labels = legend(low, high)
    root = coin.SoSeparator()
    camera = coin.SoOrthographicCamera()
    camera.height = 2.0  # x and y in [-1, 1] over the whole view, whatever its shape
    camera.viewportMapping = coin.SoCamera.LEAVE_ALONE
    root.addChild(camera)
    light = coin.SoLightModel()
    light.model = coin.SoLightModel.BASE_COLOR
    root.addChild(light)
    # Right of the model, clear of the navigation cube (top right) and the axis cross (bottom
    # right) in a landscape view; the field's name goes under the bar.
    x0, x1, y0, y1 = 0.62, 0.66, -0.7, 0.5
    step = (y1 - y0) / len(bands)
    coords = coin.SoCoordinate3()
    points = []
    for k in range(len(bands)):
        ya, yb = y0 + k * step, y0 + (k + 1) * step
        points += [(x0, ya, 0), (x1, ya, 0), (x1, yb, 0), (x0, yb, 0)]
    coords.point.setValues(0, len(points), points)
    material = coin.SoMaterial()
    material.diffuseColor.setValues(0, len(bands), [c for _, c in bands])
    binding = coin.SoMaterialBinding()
    binding.value = coin.SoMaterialBinding.PER_FACE
    faces = coin.SoFaceSet()
    faces.numVertices.setValues(0, len(bands), [4] * len(bands))
    for node in (coords, material, binding, faces):
        root.addChild(node)
    text_colour = coin.SoBaseColor()
    text_colour.rgb = (0.0, 0.0, 0.0)
    root.addChild(text_colour)
    font = coin.SoFont()
    font.size = 14
    root.addChild(font)
    for value, text in labels + [(None, ["node temperature", title])]:
        sep = coin.SoSeparator()
        move = coin.SoTranslation()
        if value is None:
            move.translation = (x0 - 0.25, y0 - 0.1, 0)
        else:
            move.translation = (x1 + 0.015, y0 + (value - low) / ((high - low) or 1.0) * (y1 - y0) - 0.015, 0)
        label = coin.SoText2()
        label.string.setValues(0, len(text), text) if isinstance(text, list) else label.string.setValue(text)
        sep.addChild(move)
        sep.addChild(label)
        root.addChild(sep)
    return root


def _recolour(mesh):
    """Per-triangle colours from the mesh's FaceColors: Coloring off and on makes the Mesh
    view provider read them again."""
    if mesh is not None and mesh.ViewObject is not None and "Coloring" in mesh.ViewObject.PropertiesList:
        mesh.ViewObject.Coloring = False
        mesh.ViewObject.Coloring = True


def _recolour_later(doc_name, result_name):
    doc = FreeCAD.listDocuments().get(doc_name)
    result = doc.getObject(result_name) if doc is not None else None
    if result is not None:
        _recolour(result.ResultMesh)


class ViewProviderThermalResult(ViewProvider):
    """Shows a ThermalResult: its mesh coloured per triangle (the mesh's FaceColors through
    the Mesh view provider's Coloring) and the colour bar over the 3D view. Double-click
    opens the result panel (table, field and time step)."""

    def __init__(self, vobj):
        super().__init__(vobj, "Result.svg")

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        self.root = coin.SoAnnotation()  # drawn last, over the model
        vobj.addDisplayMode(self.root, "ColourBar")

    def getDisplayModes(self, vobj):
        return ["ColourBar"]

    def getDefaultDisplayMode(self):
        return "ColourBar"

    def claimChildren(self):
        return []

    def updateData(self, obj, prop):
        if prop in ("ColourMinK", "ColourMaxK", "Shown") and getattr(obj, "ViewObject", None) is not None:
            self.refresh(obj.ViewObject)

    def refresh(self, vobj):
        """Redraws the colour bar and re-reads the mesh's per-triangle colours."""
        obj = vobj.Object
        root = getattr(self, "root", None)
        if root is None or obj.ColourMaxK <= obj.ColourMinK:
            return
        root.removeAllChildren()
        root.addChild(_legend_graph(obj.ColourMinK, obj.ColourMaxK, obj.Shown))
        _recolour(obj.ResultMesh)
        # Opening a document, the mesh's view is rebuilt after this runs, without colours:
        # colour it again once the event loop is back.
        from PySide import QtCore
        doc, name = obj.Document.Name, obj.Name
        QtCore.QTimer.singleShot(0, lambda: _recolour_later(doc, name))

    def onDelete(self, vobj, subelements):
        mesh = vobj.Object.ResultMesh
        if mesh is not None and mesh.ViewObject is not None and "Coloring" in mesh.ViewObject.PropertiesList:
            mesh.ViewObject.Coloring = False
        return True

    def setEdit(self, vobj, mode=0):
        import FreeCADGui
        from . import taskpanels
        FreeCADGui.Control.showDialog(taskpanels.ResultPanel(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        import FreeCADGui
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        import FreeCADGui
        FreeCADGui.activeDocument().setEdit(vobj.Object.Name)
        return True
