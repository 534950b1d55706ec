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


def mesh_object_faces(shape, label, faces, max_edge_mm, iterations=6, progress=None):
    """Meshes the given (index, face) pairs of one shape with one Mefisto target length,
    shrunk until no triangle edge exceeds max_edge_mm (Mefisto treats the length as a target:
    interior edges come out up to ~1.3x longer on planes, more on strongly curved patches).
    One target per shape keeps shared edges discretised identically on both sides.
    `progress(k)`: called after each face of a pass (k faces of this pass done).
    Returns ([(P [mm], F)], longest edge [mm])."""
    target = _closed_edge_limit(shape, max_edge_mm)
    for _ in range(iterations):
        meshes = []
        for i, face in faces:
            meshes.append(_mesh_face(face, target, "%s.Face%d" % (label, i + 1)))
            if progress:
                progress(len(meshes))
        longest = max(_max_edge(P, F) for P, F in meshes)
        if longest <= max_edge_mm:
            break
        target *= 0.97 * max_edge_mm / longest
    else:
        FreeCAD.Console.PrintWarning("ThermoDec: %s: longest edge %.4g mm > %.4g mm after %d passes\n"
                                     % (label, longest, max_edge_mm, iterations))
    return meshes, longest


def shape_groups(assignment):
    """The assignment's faces per shape object, in first-seen order: [(label, shape,
    [(face index, Part.Face, node index, material index)])]."""
    by_object = {}
    for k, (obj, i, face) in enumerate(assignment.faces):
        by_object.setdefault(obj.Name, (obj.Label, obj.Shape, []))[2].append(
            (i, face, assignment.face_node[k], assignment.face_material[k]))
    return list(by_object.values())


def tessellate_groups(groups, max_edge_mm, progress=None):
    """Dense welded mesh of shape_groups(): (V [mm] #Vx3, F #Fx3, face_node #F, face_material
    #F, longest edge [mm]). `progress(done, total)`: B-rep faces meshed (a shape meshed again
    with a shorter target counts from its first face again)."""
    if max_edge_mm <= 0:
        raise ThermoDecError("max edge length must be > 0 (got %g mm)" % max_edge_mm)
    total = sum(len(faces) for _, _, faces in groups)
    Ps, Fs, nodes, mats = [], [], [], []
    offset, before, longest = 0, 0, 0.0
    for label, shape, faces in groups:
        report = (lambda k, before=before: progress(before + k, total)) if progress else None
        meshes, obj_longest = mesh_object_faces(shape, label, [(i, face) for i, face, _, _ in faces], max_edge_mm,
                                                progress=report)
        before += len(faces)
        longest = max(longest, obj_longest)
        for (_, _, node, material), (P, F) in zip(faces, meshes):
            Ps.append(P)
            Fs.append(F + offset)
            offset += len(P)
            nodes.append(np.full(len(F), node))
            mats.append(np.full(len(F), material))
    V = np.vstack(Ps)
    F = np.vstack(Fs)
    # Weld the copies of shared-edge vertices: both faces discretise an edge identically, so
    # a tolerance far below the model size only merges true duplicates.
    extent = float(np.max(V.max(axis=0) - V.min(axis=0))) or 1.0
    welded = core.module().weld_vertices(V, extent * 1e-9)
    V = np.array(welded.V)
    F = np.array(welded.new_index, dtype=np.int64)[F]
    return V, F, np.concatenate(nodes), np.concatenate(mats), longest


def tessellate_faces(assignment, max_edge_mm):
    """Dense mesh of all assigned faces: (V [mm] #Vx3, F #Fx3, face_node #F, face_material #F,
    longest edge [mm])."""
    import os
    import tempfile
    # note: meshed as read back from BREP files, like the background process meshes them: BREP
    # keeps 15 digits, and Mefisto triangulates a curved face differently for the last digits.
    # Both paths thus give the same mesh, bit for bit.
    with tempfile.TemporaryDirectory(prefix="thermodec_tessellate_") as folder:
        groups = []
        for k, (label, shape, faces) in enumerate(shape_groups(assignment)):
            back = _through_brep(shape, os.path.join(folder, "shape%d.brep" % k))
            groups.append((label, back, [(i, back.Faces[i], n, m) for i, _, n, m in faces]))
        return tessellate_groups(groups, max_edge_mm)


def _through_brep(shape, path):
    """`shape` written to the BREP file `path` and read back."""
    import Part
    shape.exportBrep(path)
    back = Part.Shape()
    back.importBrep(path)
    return back


def tessellate(analysis, max_edge_mm=None):
    """Meshes the analysis here (the caller's thread) and stores the result in its ThermalMesh
    object (created if needed). Returns that Mesh::FeaturePython object. The Tessellate command
    runs the same meshing in a background process instead (runner.tessellate_job)."""
    assignment = assign_faces(analysis)
    for message in assignment.repairs:
        FreeCAD.Console.PrintWarning("ThermoDec: %s\n" % message)
    if max_edge_mm is None:
        max_edge_mm = float(analysis.MaxEdgeLength.getValueAs("mm"))
    V, F, face_node, face_material, longest = tessellate_faces(assignment, max_edge_mm)
    return store(analysis, assignment, V, F, face_node, face_material, longest, max_edge_mm)


def store(analysis, assignment, V, F, face_node, face_material, longest, max_edge_mm):
    """The analysis' ThermalMesh (created if needed) set to the mesh V [mm], F with its tags."""
    import Mesh
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


# ---------------------------------------------------------------------------------------------
# The same meshing in a background process (the Tessellate command): FreeCAD's shapes are
# document objects only the GUI thread may touch, and OpenCASCADE's mesher holds the Python lock
# while it runs, so a Python thread would freeze the GUI as well. The GUI thread writes each
# shape as a BREP file with the face assignment (write_job, quick); `freecadcmd` meshes them
# (tessellate_worker.py, the functions above); the GUI thread stores the result (import_job).

def fingerprint(assignment):
    """What the mesh of an assignment depends on, to tell whether the analysis changed while a
    background tessellation ran: per face its shape, index, node, material, area and bounds."""
    out = [[objects.model_name(n) for n in assignment.nodes], [objects.model_name(m) for m in assignment.materials]]
    for k, (obj, i, face) in enumerate(assignment.faces):
        b = face.BoundBox
        out.append([obj.Name, i, int(assignment.face_node[k]), int(assignment.face_material[k]),
                    "%.9g" % face.Area] + ["%.9g" % v for v in (b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax)])
    return out


def write_job(analysis, folder, max_edge_mm=None):
    """Writes what the background tessellation needs into `folder`: one BREP per shape object
    and job.json (faces, their nodes and materials, the max edge length [mm]). Checks the
    assignment first (the errors of assign_faces). Returns the job's outputs dict."""
    import json
    import os
    from .files import atomic_write_text
    assignment = assign_faces(analysis)
    for message in assignment.repairs:
        FreeCAD.Console.PrintWarning("ThermoDec: %s\n" % message)
    if max_edge_mm is None:
        max_edge_mm = float(analysis.MaxEdgeLength.getValueAs("mm"))
    if max_edge_mm <= 0:
        raise ThermoDecError("max edge length must be > 0 (got %g mm)" % max_edge_mm)
    os.makedirs(folder, exist_ok=True)
    groups = []
    for k, (label, shape, faces) in enumerate(shape_groups(assignment)):
        brep = os.path.join(folder, "shape%d.brep" % k)
        shape.exportBrep(brep)
        groups.append({"label": label, "brep": brep, "faces": [[int(i), int(n), int(m)] for i, _, n, m in faces]})
    spec = {"max_edge_mm": max_edge_mm, "groups": groups, "faces": len(assignment.faces),
            "output": os.path.join(folder, "mesh.npz"), "fingerprint": fingerprint(assignment)}
    job_path = os.path.join(folder, "job.json")
    if os.path.exists(spec["output"]):
        os.unlink(spec["output"])  # a cancelled or failed run never leaves an older mesh to import
    atomic_write_text(job_path, json.dumps(spec) + "\n")
    return {"job": job_path, "mesh": spec["output"], "max_edge_mm": max_edge_mm, "faces": len(assignment.faces)}


def run_job(job_path, progress=None):
    """Meshes a write_job folder (tessellate_worker.py runs this in `freecadcmd`) and writes
    its mesh.npz atomically. Returns the number of triangles."""
    import json
    import os
    import tempfile
    import Part
    with open(job_path, encoding="utf-8") as f:
        spec = json.load(f)
    groups = []
    for g in spec["groups"]:
        shape = Part.Shape()
        shape.importBrep(g["brep"])  # as tessellate_faces reads it back
        groups.append((g["label"], shape, [(i, shape.Faces[i], n, m) for i, n, m in g["faces"]]))
    V, F, face_node, face_material, longest = tessellate_groups(groups, spec["max_edge_mm"], progress)
    fd, tmp = tempfile.mkstemp(prefix=".mesh.npz.tmp-", suffix=".npz", dir=os.path.dirname(spec["output"]))
    with os.fdopen(fd, "wb") as f:
        np.savez(f, V=V, F=F, face_node=face_node, face_material=face_material, longest=longest)
    os.replace(tmp, spec["output"])
    return len(F)


def import_job(analysis, outputs):
    """Stores a background tessellation (write_job's outputs, meshed by run_job) in the
    analysis' ThermalMesh, unless the analysis changed meanwhile (then an error: tessellate
    again). Returns the ThermalMesh."""
    import json
    assignment = assign_faces(analysis)
    with open(outputs["job"], encoding="utf-8") as f:
        meshed = json.load(f)["fingerprint"]
    if fingerprint(assignment) != meshed:
        raise ThermoDecError("the analysis' shapes, nodes or materials changed while tessellating: tessellate again")
    with np.load(outputs["mesh"]) as data:
        V, F = data["V"], data["F"]
        face_node, face_material, longest = data["face_node"], data["face_material"], float(data["longest"])
    return store(analysis, assignment, V, F, face_node, face_material, longest, outputs["max_edge_mm"])


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
