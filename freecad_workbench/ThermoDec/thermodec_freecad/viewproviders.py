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


class ViewProviderThermalMesh(ViewProvider):
    def __init__(self, vobj):
        super().__init__(vobj, "Tessellate.svg")

    def claimChildren(self):
        return []


def _palette(k):
    # Distinct, stable colours per node index (golden-ratio hue walk).
    import colorsys
    h = (k * 0.618033988749895) % 1.0
    return colorsys.hsv_to_rgb(h, 0.55, 0.95)


def _heat(t):
    # Blue -> cyan -> green -> yellow -> red for t in [0, 1].
    import colorsys
    t = min(max(t, 0.0), 1.0)
    return colorsys.hsv_to_rgb((1.0 - t) * 2.0 / 3.0, 0.9, 0.95)


def _colour_faces(obj, colours):
    """Per-triangle colours on a Mesh feature: one segment per colour, highlighted."""
    import Mesh
    mesh = Mesh.Mesh(obj.Mesh.Topology)  # same points and facets, no earlier segments
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
