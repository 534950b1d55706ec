"""Exported files read by tools nobody here wrote: meshio (NASTRAN .bdf and VTK .vtu) and gmsh
(.bdf). Each must see the same vertices, the same triangles and the same thermal node per
triangle as the model's own mesh (the OBJ, read here by a few lines of Python).

usage: external_readers.py THERMODEC MODEL.json WORKDIR [--vtk]
Exit 77 (CTest SKIP_RETURN_CODE) with a message when python3-meshio or gmsh is missing.
"""
import os
import re
import shutil
import subprocess
import sys


def skip(why):
    print("SKIP: " + why + " (install python3-meshio and gmsh: scripts/setup does)")
    sys.exit(77)


try:
    import meshio
    import numpy as np
except ImportError as e:
    skip("python module missing: %s" % e)
if shutil.which("gmsh") is None:
    skip("gmsh not on PATH")

thermodec, model, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)


def run(*args):
    r = subprocess.run([thermodec, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("thermodec %s failed: %s" % (" ".join(args), r.stderr))


def read_obj(path):
    """Vertices and triangles with their group (= thermal node) name."""
    v, faces, group = [], [], None
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w[0] in ("g", "o"):
            group = " ".join(w[1:])
        elif w[0] == "f":
            idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
            for k in range(1, len(idx) - 1):
                faces.append(((idx[0], idx[k], idx[k + 1]), group))
    return np.array(v), faces


def keyed(points, tris, names):
    """{sorted corner coordinates (rounded to 1e-9 m): node name}: independent of numbering."""
    out = {}
    for tri, name in zip(tris, names):
        key = tuple(sorted(tuple(np.round(points[i], 9)) for i in tri))
        out[key] = name
    return out


def comment_names(path, kind):
    names = {}
    for line in open(path):
        m = re.match(r"^\$ thermodec %s (\d+) (.+)$" % kind, line.rstrip("\n"))
        if m:
            names[int(m.group(1))] = m.group(2)
    return names


failures = []


def check(what, got, want):
    if got != want:
        failures.append("%s: differs" % what)
        missing = set(want) - set(got)
        extra = set(got) - set(want)
        wrong = [k for k in want if k in got and got[k] != want[k]]
        print("%s: %d triangles missing, %d extra, %d with another node" % (what, len(missing), len(extra), len(wrong)))
    else:
        print("%s: %d triangles, same corners and nodes" % (what, len(got)))


mesh_path = os.path.join(os.path.dirname(model), re.search(r'"mesh"\s*:\s*"([^"]+)"', open(model).read()).group(1))
obj_v, obj_f = read_obj(mesh_path)
want = keyed(obj_v, [t for t, _ in obj_f], [g for _, g in obj_f])

bdf = os.path.join(work, "model.bdf")
run("export", model, "--format", "nastran", "-o", bdf, "-q")
pid_names = comment_names(bdf, "node")

m = meshio.read(bdf, file_format="nastran")
tri = np.concatenate([c.data for c in m.cells if c.type == "triangle"])
refs = np.concatenate(m.cell_data["nastran:ref"])
check("meshio .bdf", keyed(m.points, tri, [pid_names[int(r)] for r in refs]), want)
if len(m.points) != len(obj_v):
    failures.append("meshio .bdf: %d vertices, the OBJ %d" % (len(m.points), len(obj_v)))

msh = os.path.join(work, "model_gmsh.msh")
r = subprocess.run(["gmsh", bdf, "-0", "-format", "msh22", "-o", msh], capture_output=True, text=True)
if r.returncode != 0:
    sys.exit("gmsh could not read %s: %s" % (bdf, r.stdout + r.stderr))
g = meshio.read(msh)
gtri = np.concatenate([c.data for c in g.cells if c.type == "triangle"])
# gmsh keeps each element's property id as its elementary (geometrical) entity tag.
gref = np.concatenate([d for c, d in zip(g.cells, g.cell_data["gmsh:geometrical"]) if c.type == "triangle"])
check("gmsh .bdf", keyed(g.points, gtri, [pid_names[int(r)] for r in gref]), want)

if "--vtk" in sys.argv:
    vtk = os.path.join(work, "vtk")
    run("export", model, "--format", "vtk", "-o", vtk, "-q", "--rays", "200", "--noise-target", "0")
    stem = os.path.splitext(os.path.basename(model))[0]
    vtu = os.path.join(vtk, stem + "_0000.vtu")
    node_names = {}
    for line in open(vtu):
        mm = re.match(r"^<!-- node (\d+): (.+) -->$", line.rstrip("\n"))
        if mm:
            node_names[int(mm.group(1))] = mm.group(2)
    v = meshio.read(vtu)
    vtri = np.concatenate([c.data for c in v.cells if c.type == "triangle"])
    ids = np.concatenate(v.cell_data["node_id"])
    check("meshio .vtu", keyed(v.points, vtri, [node_names[int(i)] for i in ids]), want)
    temps = np.concatenate(v.cell_data["temperature_K"])
    if not (np.all(np.isfinite(temps)) and temps.min() > 2.7 and temps.max() < 1000):
        failures.append("meshio .vtu: temperatures outside (2.7, 1000) K")

if failures:
    sys.exit("FAILED: " + "; ".join(failures))
print("all readers agree")
