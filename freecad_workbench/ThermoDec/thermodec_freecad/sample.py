"""A satellite like the paper's, from B-rep primitives (mm): a 1 m box body, two thin solar
wings, a boom and a parabolic-like (spherical cap) dish antenna. Used by the tests, the GUI
demo script and as a template for scripting the workbench."""

import FreeCAD
from FreeCAD import Vector

from . import objects


def build_shapes(doc):
    """Adds Part::Feature objects Body, WingPlusY, WingMinusY, Boom, Dish. Returns them by name."""
    import Part
    shapes = {
        "Body": Part.makeBox(1000, 1000, 1000, Vector(-500, -500, -500)),
        "WingPlusY": Part.makeBox(800, 1800, 20, Vector(-400, 600, -10)),
        "WingMinusY": Part.makeBox(800, 1800, 20, Vector(-400, -2400, -10)),
        "Boom": Part.makeCylinder(25, 400, Vector(0, 0, 500), Vector(0, 0, 1)),
    }
    # Dish: 20 mm thick spherical shell cap (radius 900 mm), opening towards +Z, resting on the boom.
    centre = Vector(0, 0, 900 + 900)
    outer = Part.makeSphere(900, centre, Vector(0, 0, -1), 60, 90)
    inner = Part.makeSphere(880, centre, Vector(0, 0, -1), 60, 90)
    shapes["Dish"] = outer.cut(inner)
    out = {}
    for name, shape in shapes.items():
        obj = doc.addObject("Part::Feature", name)
        obj.Shape = shape
        out[name] = obj
    doc.recompute()
    return out


def _face_towards(obj, direction):
    """Name of the planar face of obj whose outward normal is closest to direction."""
    best, name = -2.0, None
    for i, f in enumerate(obj.Shape.Faces):
        u0, u1, v0, v1 = f.ParameterRange
        n = f.normalAt((u0 + u1) / 2, (v0 + v1) / 2)
        if n.dot(direction) > best:
            best, name = n.dot(direction), "Face%d" % (i + 1)
    return name


def build_analysis(doc, shapes=None, max_edge="150 mm"):
    """The full thermal set-up of the sample: nodes, coatings, conductances, orbit.
    Returns the ThermalAnalysis."""
    shapes = shapes or build_shapes(doc)
    analysis = objects.makeAnalysis(doc)
    analysis.MaxEdgeLength = max_edge
    analysis.RaysPerFace = 200
    white = objects.makeMaterial(analysis, "white_paint")
    mli = objects.makeMaterial(analysis, "mli_outer_layer")
    osr = objects.makeMaterial(analysis, "osr")
    cells = objects.makeMaterial(analysis, "solar_cell")
    alu = objects.makeMaterial(analysis, "bare_aluminium")
    analysis.DefaultMaterial = white

    body_nodes = objects.automatic_nodes(analysis, [shapes["Body"]], per="face", material=mli)
    axes = {"px": Vector(1, 0, 0), "mx": Vector(-1, 0, 0), "py": Vector(0, 1, 0),
            "my": Vector(0, -1, 0), "pz": Vector(0, 0, 1), "mz": Vector(0, 0, -1)}
    for node in body_nodes:
        sub = node.References[0][1][0]
        for axis, d in axes.items():
            if _face_towards(shapes["Body"], d) == sub:
                node.Label = "body_" + axis
    by_label = {n.Label: n for n in body_nodes}
    by_label["body_pz"].Material = osr  # radiator, faces the dish side
    by_label["body_mz"].Material = white
    for n in body_nodes:
        n.Capacitance = 8000.0
    by_label["body_px"].Power = 40.0
    by_label["body_mx"].Power = 40.0

    wings = []
    for side in ("PlusY", "MinusY"):
        wing = shapes["Wing" + side]
        node = objects.makeNode(analysis, [(wing, "")], name="wing_" + side.lower(), material=white,
                                capacitance=3000.0)
        node.Label = "wing_" + side.lower()
        objects.assign_material(cells, [(wing, _face_towards(wing, Vector(0, 0, 1)))])
        wings.append(node)
    boom = objects.makeNode(analysis, [(shapes["Boom"], "")], name="boom", material=alu, capacitance=200.0)
    dish = objects.makeNode(analysis, [(shapes["Dish"], "")], name="dish", material=white, capacitance=1500.0)

    for node in wings:
        objects.makeConductance(analysis, by_label["body_py" if "plus" in node.Label else "body_my"],
                                node, 0.5, name="hinge_" + node.Label)
    objects.makeConductance(analysis, by_label["body_pz"], boom, 0.3, name="boom_mount")
    objects.makeConductance(analysis, boom, dish, 0.2, name="dish_mount")
    objects.makeEnvironment(analysis, "orbit", Altitude="600 km", Inclination=98.0, Attitude="nadir")
    doc.recompute()
    return analysis
