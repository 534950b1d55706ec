"""Dense tessellation of the analysis' geometry with every triangle tagged by node and material.

FreeCAD's Standard mesher keeps one segment per B-rep face but never subdivides planar faces;
Mefisto honours a max edge length but returns no segments. So each B-rep face is meshed on
its own with Mefisto (it discretises a shared edge identically from both sides) and the face
meshes are welded back together: the result is conforming and each triangle knows its face.
"""

import numpy as np

import FreeCAD

from . import core, objects, references
from .errors import ThermoDecError


class FaceAssignment:
    """Which node and material every B-rep face of the analysis' shapes belongs to."""

    def __init__(self):
        self.faces = []          # [(shape object, face index, Part.Face)]
        self.face_node = []      # node index per face, into self.nodes
        self.face_material = []  # material index per face, into self.materials
        self.nodes = []          # ThermalNode objects
        self.materials = []      # ThermalMaterial objects
        self.repairs = []        # messages about references repaired after a recompute


def _check_material(mat):
    for prop in ("Absorptivity", "Emissivity"):
        value = getattr(mat, prop)
        if not (0.0 < value <= 1.0):
            raise ThermoDecError("material '%s': %s = %g is outside (0, 1]" % (mat.Label, prop, value))


def assign_faces(analysis):
    """Resolves nodes and materials to B-rep faces. Raises ThermoDecError for nodes without
    faces, faces in two nodes, faces in no node, nodes without material, empty shapes."""
    out = FaceAssignment()
    nodes = objects.members(analysis, objects.ThermalNode)
    if not nodes:
        raise ThermoDecError("analysis '%s' has no thermal node" % analysis.Label)
    owner = {}  # (object name, face index) -> node index
    shape_objs = []
    for n, node in enumerate(nodes):
        out.repairs += references.check(node)
        count = 0
        for obj, subs in node.References:
            if obj.Shape.isNull() or not obj.Shape.Faces:
                raise ThermoDecError("node '%s': '%s' has an empty shape" % (node.Label, obj.Label))
            if obj not in shape_objs:
                shape_objs.append(obj)
            for s in references.expand(obj, subs):
                key = (obj.Name, references.face_index(s))
                if key in owner:
                    raise ThermoDecError("face %s.%s is in two nodes: '%s' and '%s'" %
                                         (obj.Label, s, nodes[owner[key]].Label, node.Label))
                owner[key] = n
                count += 1
        if count == 0:
            raise ThermoDecError("node '%s' covers no face" % node.Label)

    overrides = {}  # (object name, face index) -> material object
    for mat in objects.members(analysis, objects.ThermalMaterial):
        out.repairs += references.check(mat)
        for obj, subs in mat.References:
            for s in references.expand(obj, subs):
                overrides[(obj.Name, references.face_index(s))] = mat

    unassigned = []
    material_index = {}
    for obj in shape_objs:
        for i, face in enumerate(obj.Shape.Faces):
            key = (obj.Name, i)
            if key not in owner:
                unassigned.append("%s.Face%d" % (obj.Label, i + 1))
                continue
            node = nodes[owner[key]]
            mat = overrides.get(key) or node.Material or analysis.DefaultMaterial
            if mat is None:
                raise ThermoDecError("node '%s' has no material and analysis '%s' has no "
                                     "DefaultMaterial" % (node.Label, analysis.Label))
            if mat.Name not in material_index:
                _check_material(mat)
                material_index[mat.Name] = len(out.materials)
                out.materials.append(mat)
            out.faces.append((obj, i, face))
            out.face_node.append(owner[key])
            out.face_material.append(material_index[mat.Name])
    if unassigned:
        shown = ", ".join(unassigned[:8]) + (", ..." if len(unassigned) > 8 else "")
        raise ThermoDecError("%d face(s) belong to no thermal node: %s" % (len(unassigned), shown))
    out.nodes = nodes
    return out


def _mesh_face(face, max_edge_mm, label):
    import MeshPart
    mesh = MeshPart.meshFromShape(Shape=face, MaxLength=max_edge_mm)
    points, facets = mesh.Topology
    if not facets:
        raise ThermoDecError("tessellation of %s gave no triangle (max edge length %g mm)" %
                             (label, max_edge_mm))
    P = np.array([(p.x, p.y, p.z) for p in points], dtype=float)
    F = np.array(facets, dtype=np.int64)
    # Triangles are counter-clockwise seen from the emitting side, i.e. along the face's
    # outward normal; Mefisto follows the face orientation, checked here on the largest triangle.
    cross = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    t = int(np.argmax(np.einsum("ij,ij->i", cross, cross)))
    centre = FreeCAD.Vector(*P[F[t]].mean(axis=0))
    u, v = face.Surface.parameter(centre)
    normal = face.normalAt(u, v)
    if np.dot(cross[t], (normal.x, normal.y, normal.z)) < 0:
        F = F[:, [0, 2, 1]]
    return P, F


def _closed_edge_limit(shape, max_edge_mm):
    """Mefisto needs 3 segments on a closed edge (a circle): the max edge length it may use."""
    closed = [e.Length for e in shape.Edges
              if e.isClosed() and not e.Degenerated and e.Length > 1e-3]
    return min([max_edge_mm] + [0.999 * length / 3 for length in closed])


def _max_edge(P, F):
    E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return float(np.max(np.linalg.norm(P[E[:, 0]] - P[E[:, 1]], axis=1)))


def mesh_object_faces(obj, faces, max_edge_mm, iterations=6):
    """Meshes the given (index, face) pairs of one shape object with one Mefisto target length,
    shrunk until no triangle edge exceeds max_edge_mm (Mefisto treats the length as a target:
    interior edges come out up to ~1.3x longer on planes, more on strongly curved patches).
    One target per object keeps shared edges discretised identically on both sides.
    Returns ([(P [mm], F)], longest edge [mm])."""
    target = _closed_edge_limit(obj.Shape, max_edge_mm)
    for _ in range(iterations):
        meshes = [_mesh_face(face, target, "%s.Face%d" % (obj.Label, i + 1)) for i, face in faces]
        longest = max(_max_edge(P, F) for P, F in meshes)
        if longest <= max_edge_mm:
            break
        target *= 0.97 * max_edge_mm / longest
    else:
        FreeCAD.Console.PrintWarning("ThermoDec: %s: longest edge %.4g mm > %.4g mm after %d passes\n"
                                     % (obj.Label, longest, max_edge_mm, iterations))
    return meshes, longest


def tessellate_faces(assignment, max_edge_mm):
    """Dense mesh of all assigned faces: (V [mm] #Vx3, F #Fx3, face_node #F, face_material #F,
    longest edge [mm])."""
    if max_edge_mm <= 0:
        raise ThermoDecError("max edge length must be > 0 (got %g mm)" % max_edge_mm)
    by_object = {}
    for k, (obj, i, face) in enumerate(assignment.faces):
        by_object.setdefault(obj.Name, (obj, []))[1].append(k)
    Ps, Fs, nodes, mats = [], [], [], []
    offset = 0
    longest = 0.0
    for obj, ks in by_object.values():
        meshes, obj_longest = mesh_object_faces(obj, [assignment.faces[k][1:] for k in ks], max_edge_mm)
        longest = max(longest, obj_longest)
        for k, (P, F) in zip(ks, meshes):
            Ps.append(P)
            Fs.append(F + offset)
            offset += len(P)
            nodes.append(np.full(len(F), assignment.face_node[k]))
            mats.append(np.full(len(F), assignment.face_material[k]))
    V = np.vstack(Ps)
    F = np.vstack(Fs)
    # Weld the copies of shared-edge vertices: both faces discretise an edge identically, so
    # a tolerance far below the model size only merges true duplicates.
    extent = float(np.max(V.max(axis=0) - V.min(axis=0))) or 1.0
    welded = core.module().weld_vertices(V, extent * 1e-9)
    V = np.array(welded.V)
    F = np.array(welded.new_index, dtype=np.int64)[F]
    return V, F, np.concatenate(nodes), np.concatenate(mats), longest


def tessellate(analysis, max_edge_mm=None):
    """Meshes the analysis and stores the result in its ThermalMesh object (created if needed).
    Returns that Mesh::FeaturePython object."""
    import Mesh
    assignment = assign_faces(analysis)
    for message in assignment.repairs:
        FreeCAD.Console.PrintWarning("ThermoDec: %s\n" % message)
    if max_edge_mm is None:
        max_edge_mm = float(analysis.MaxEdgeLength.getValueAs("mm"))
    V, F, face_node, face_material, longest = tessellate_faces(assignment, max_edge_mm)

    mesh = Mesh.Mesh(([FreeCAD.Vector(*p) for p in V], [tuple(int(j) for j in t) for t in F]))
    if mesh.CountFacets != len(F):
        raise ThermoDecError("FreeCAD's mesh kept %d of %d triangles" % (mesh.CountFacets, len(F)))
    obj = analysis.ThermalMesh
    if obj is None:
        obj = analysis.Document.addObject("Mesh::FeaturePython", "ThermalMesh")
        ThermalMesh(obj)
        if FreeCAD.GuiUp:
            from . import viewproviders
            viewproviders.ViewProviderThermalMesh(obj.ViewObject)
        analysis.addObject(obj)
        analysis.ThermalMesh = obj
    obj.Mesh = mesh
    obj.FaceNode = [int(x) for x in face_node]
    obj.FaceMaterial = [int(x) for x in face_material]
    obj.NodeNames = [objects.model_name(n) for n in assignment.nodes]
    obj.MaterialNames = [objects.model_name(m) for m in assignment.materials]
    obj.MaxEdgeLength = max_edge_mm
    obj.LongestEdge = longest
    if FreeCAD.GuiUp:
        from . import viewproviders
        viewproviders.colour_by_node(obj)
    return obj


def mesh_arrays(thermal_mesh):
    """(V [mm] #Vx3 float, F #Fx3 int) of a ThermalMesh, in facet order (tags line up)."""
    points, facets = thermal_mesh.Mesh.Topology
    V = np.array([(p.x, p.y, p.z) for p in points], dtype=float)
    F = np.array(facets, dtype=np.int64).reshape(-1, 3)
    return V, F


class ThermalMesh(objects._Proxy):
    """Dense mesh with per-triangle node and material (indices into NodeNames/MaterialNames)."""
    Type = "ThermoDec::ThermalMesh"

    def onChanged(self, obj, prop):
        # Re-tessellated (its tags rewritten): the analysis' results are of the old mesh.
        # Colours and shown temperatures are outputs.
        if prop in ("FaceNode", "FaceMaterial") and not obj.Document.Restoring:
            analysis = objects.find_analysis(obj)
            if analysis is not None and analysis.ThermalMesh == obj:
                objects.stale(analysis, "'%s' was tessellated again" % obj.Label)

    def setup(self, obj):
        g = "Thermal tags"
        objects._add(obj, "App::PropertyIntegerList", "FaceNode", g, "Node index per triangle")
        objects._add(obj, "App::PropertyIntegerList", "FaceMaterial", g, "Material index per triangle")
        objects._add(obj, "App::PropertyStringList", "NodeNames", g, "Node names")
        objects._add(obj, "App::PropertyStringList", "MaterialNames", g, "Material names")
        objects._add(obj, "App::PropertyFloat", "MaxEdgeLength", g, "Max edge length asked for [mm]")
        objects._add(obj, "App::PropertyFloat", "LongestEdge", g, "Longest triangle edge obtained [mm]")
        objects._add(obj, "App::PropertyFloatList", "FaceTemperature", "Results",
                     "Temperature per triangle [K] (imported results)")
