#!/usr/bin/python3
"""Generates thermodec's sample satellite: a nadir-pointing box spacecraft like the one of the
paper's figures (box body with six panel nodes, two solar wings on yokes, a parabolic dish on a
boom, an instrument box), as a coarse mesh (~1000 triangles) and a dense one (~20k triangles)
of the same craft, each with its thermal model file.

    /usr/bin/python3 generate_satellite.py [OUTPUT_DIR]     (default: this script's folder)
    /usr/bin/python3 generate_satellite.py --refine K OUTPUT_DIR

The second form writes only satellite_kK.obj and model_kK.json: every grid refined K times, the
dish 10 K rings x 32 K segments (K = 4 is the dense variant; K = 9 about 100k triangles), for
scale benchmarks (scripts/bench_scale).

Standard library only and deterministic: rerunning rewrites byte-identical files.

Body axes (metres): +Z nadir (towards the Earth), +X along the velocity, +Y completing the
right-handed frame (anti-normal of the orbit). The body is the box |x| <= 0.5, |y| <= 0.5,
|z| <= 0.6. Every part is meshed on a regular grid whose lines meet the neighbouring parts'
grid lines, so the mesh is conforming: parts that touch share their vertices there.
"""
import json
import math
import os
import sys

# --- thermo-optical coatings (beginning-of-life values, diffuse grey) -------------------------
MATERIALS = {
    # white silicone paint (e.g. SG121FD class)
    "white_paint": {"absorptivity": 0.20, "emissivity": 0.85},
    # outer layer of the MLI blankets: aluminised Kapton, Kapton side out
    "mli_kapton": {"absorptivity": 0.40, "emissivity": 0.70},
    # optical solar reflector tiles (silvered quartz) of the radiator
    "osr": {"absorptivity": 0.08, "emissivity": 0.80},
    # triple-junction solar cells with cover glass
    "solar_cell": {"absorptivity": 0.92, "emissivity": 0.85},
    # black paint of the instrument's aperture baffle
    "black_paint": {"absorptivity": 0.95, "emissivity": 0.88},
}

# Display colours for the .mtl file (viewers only; thermodec reads the model file).
COLOURS = {
    "white_paint": (0.92, 0.92, 0.92),
    "mli_kapton": (0.85, 0.60, 0.15),
    "osr": (0.75, 0.80, 0.90),
    "solar_cell": (0.10, 0.15, 0.45),
    "black_paint": (0.05, 0.05, 0.05),
}


class MeshBuilder:
    """Indexed triangle mesh with a group (thermal node) and a material per face. Vertices
    are welded on coordinates rounded to 1e-9 m, so grids that meet share their vertices."""

    def __init__(self):
        self.vertices = []
        self.index = {}
        self.faces = []  # (node, material, (a, b, c)), counter-clockwise seen from the front

    def vertex(self, p):
        key = tuple(round(c, 9) + 0.0 for c in p)  # + 0.0 turns -0.0 into 0.0
        if key not in self.index:
            self.index[key] = len(self.vertices)
            self.vertices.append(key)
        return self.index[key]

    def triangle(self, node, material, a, b, c):
        self.faces.append((node, material, (a, b, c)))


def add(p, q, s=1.0):
    return tuple(pi + s * qi for pi, qi in zip(p, q))


def grid(mesh, node, origin, u, v, nu, nv, material, skip=lambda i, j: False):
    """Rectangle origin + s*u + t*v, s,t in [0,1], as nu x nv cells of two triangles each.
    The front (normal u x v) is the emitting side. `material(i, j)` names each cell's coating;
    cells where skip(i, j) are left out (a hole where another part is attached)."""
    def p(i, j):
        return mesh.vertex(add(add(origin, u, i / nu), v, j / nv))

    for j in range(nv):
        for i in range(nu):
            if skip(i, j):
                continue
            a, b, c, d = p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)
            m = material(i, j)
            mesh.triangle(node, m, a, b, c)
            mesh.triangle(node, m, a, c, d)


def box_side(mesh, node, origin, u, v, nu, nv, material, outward, skip=lambda i, j: False):
    """grid() whose front faces `outward`: when u x v points inwards, swap u and v."""
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    if sum(a * b for a, b in zip(n, outward)) > 0:
        grid(mesh, node, origin, u, v, nu, nv, material, skip)
    else:
        grid(mesh, node, origin, v, u, nv, nu, lambda i, j: material(j, i), lambda i, j: skip(j, i))


def build(k, dish_rings, dish_segments, wing_span_cells=None):
    """The craft with every grid refined k times (k = 1: 0.2 m body cells); the dish has
    dish_rings x dish_segments cells; each wing has wing_span_cells cells along its 2 m span
    (default 10 k)."""
    if wing_span_cells is None:
        wing_span_cells = 10 * k
    m = MeshBuilder()
    c = 0.2 / k  # body cell size [m]
    nx, ny, nz = 5 * k, 5 * k, 6 * k
    X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)

    def const(name):
        return lambda i, j: name

    def sx(v):
        return tuple(1.0 * a for a in v)

    # --- body: six panels, one node each --------------------------------------------------
    # Cells of the nadir panel covered by the boom foot (x in [-0.3,-0.1], y in [-0.1,0.1])
    # and by the instrument (x in [0.1,0.3], y in [-0.3,0.3]) are left out: body, boom and
    # instrument form one closed surface.
    def pz_skip(i, j):
        boom = k <= i < 2 * k and 2 * k <= j < 3 * k
        instrument = 3 * k <= i < 4 * k and k <= j < 4 * k
        return boom or instrument

    # OSR radiator on the -Y panel (never sunlit in this orbit), |x| <= 0.3, |z| <= 0.4, in a
    # white-painted frame: one node, two coatings.
    def my_material(i, j):  # i along x, j along z
        x0, z0 = -0.5 + i * c, -0.6 + j * c
        inside = -0.3 - 1e-9 <= x0 and x0 + c <= 0.3 + 1e-9 and -0.4 - 1e-9 <= z0 and z0 + c <= 0.4 + 1e-9
        return "osr" if inside else "white_paint"

    box_side(m, "body_px", (0.5, -0.5, -0.6), sx(Y), (0.0, 0.0, 1.2), ny, nz, const("mli_kapton"), X)
    box_side(m, "body_mx", (-0.5, -0.5, -0.6), sx(Y), (0.0, 0.0, 1.2), ny, nz, const("mli_kapton"), (-1, 0, 0))
    box_side(m, "body_py", (-0.5, 0.5, -0.6), sx(X), (0.0, 0.0, 1.2), nx, nz, const("mli_kapton"), Y)
    box_side(m, "body_my", (-0.5, -0.5, -0.6), sx(X), (0.0, 0.0, 1.2), nx, nz, my_material, (0, -1, 0))
    box_side(m, "body_pz", (-0.5, -0.5, 0.6), sx(X), sx(Y), nx, ny, const("white_paint"), Z, pz_skip)
    box_side(m, "body_mz", (-0.5, -0.5, -0.6), sx(X), sx(Y), nx, ny, const("mli_kapton"), (0, 0, -1))

    # --- boom: square tube 0.2 x 0.2 m, 0.5 m long, on the nadir panel ----------------------
    bl = 4 * k  # cells along the boom
    z0, z1 = 0.6, 1.1
    box_side(m, "boom", (-0.1, -0.1, z0), (0.0, 0.2, 0.0), (0.0, 0.0, z1 - z0), k, bl, const("white_paint"), X)
    box_side(m, "boom", (-0.3, -0.1, z0), (0.0, 0.2, 0.0), (0.0, 0.0, z1 - z0), k, bl, const("white_paint"), (-1, 0, 0))
    box_side(m, "boom", (-0.3, 0.1, z0), (0.2, 0.0, 0.0), (0.0, 0.0, z1 - z0), k, bl, const("white_paint"), Y)
    box_side(m, "boom", (-0.3, -0.1, z0), (0.2, 0.0, 0.0), (0.0, 0.0, z1 - z0), k, bl, const("white_paint"), (0, -1, 0))
    # Top cap: a fan around the centre, which is also the dish's apex (their contact point).
    apex = (-0.2, 0.0, z1)
    ring = []  # cap boundary, counter-clockwise seen from +Z
    for s in range(k):
        ring.append((-0.3 + 0.2 * s / k, -0.1, z1))
    for s in range(k):
        ring.append((-0.1, -0.1 + 0.2 * s / k, z1))
    for s in range(k):
        ring.append((-0.1 - 0.2 * s / k, 0.1, z1))
    for s in range(k):
        ring.append((-0.3, 0.1 - 0.2 * s / k, z1))
    centre = m.vertex(apex)
    for s in range(len(ring)):
        m.triangle("boom", "white_paint", centre, m.vertex(ring[s]), m.vertex(ring[(s + 1) % len(ring)]))

    # --- parabolic dish: diameter 0.8 m, focal length 0.3 m, opening to nadir -----------------
    # Thin two-sided reflector: white-painted concave front, MLI on the back.
    radius, focal = 0.4, 0.3

    def dish_point(r, phi):
        return (apex[0] + r * math.cos(phi), apex[1] + r * math.sin(phi), apex[2] + r * r / (4.0 * focal))

    rings = [[m.vertex(dish_point(radius * (q + 1) / dish_rings, 2.0 * math.pi * s / dish_segments))
              for s in range(dish_segments)] for q in range(dish_rings)]
    for s in range(dish_segments):
        m.triangle("dish", "white_paint", centre, rings[0][s], rings[0][(s + 1) % dish_segments])
    for q in range(dish_rings - 1):
        inner, outer = rings[q], rings[q + 1]
        for s in range(dish_segments):
            t = (s + 1) % dish_segments
            m.triangle("dish", "white_paint", inner[s], outer[s], outer[t])
            m.triangle("dish", "white_paint", inner[s], outer[t], inner[t])

    # --- instrument: 0.2 x 0.6 x 0.2 m box on the nadir panel, black aperture on top -----------
    box_side(m, "instrument", (0.1, -0.3, 0.8), (0.2, 0.0, 0.0), (0.0, 0.6, 0.0), k, 3 * k, const("black_paint"), Z)
    box_side(m, "instrument", (0.3, -0.3, 0.6), (0.0, 0.6, 0.0), (0.0, 0.0, 0.2), 3 * k, k, const("mli_kapton"), X)
    box_side(m, "instrument", (0.1, -0.3, 0.6), (0.0, 0.6, 0.0), (0.0, 0.0, 0.2), 3 * k, k, const("mli_kapton"), (-1, 0, 0))
    box_side(m, "instrument", (0.1, 0.3, 0.6), (0.2, 0.0, 0.0), (0.0, 0.0, 0.2), k, k, const("mli_kapton"), Y)
    box_side(m, "instrument", (0.1, -0.3, 0.6), (0.2, 0.0, 0.0), (0.0, 0.0, 0.2), k, k, const("mli_kapton"), (0, -1, 0))

    # --- solar wings: yokes 0.3 m long, then two 1.0 x 1.0 m panels, in the plane z = 0 -------
    # Thin two-sided sheets; cells face zenith (-Z), painted backs face nadir. The yoke's root
    # edge lies on a grid line of the side panel (a T-joint sharing its vertices), its tip edge
    # on the wing's root edge.
    zen = (0, 0, -1)
    box_side(m, "yoke_py", (-0.1, 0.5, 0.0), (0.2, 0.0, 0.0), (0.0, 0.3, 0.0), k, 3 * k, const("white_paint"), zen)
    box_side(m, "wing_py", (-0.5, 0.8, 0.0), sx(X), (0.0, 2.0, 0.0), nx, wing_span_cells, const("solar_cell"), zen)
    box_side(m, "yoke_my", (-0.1, -0.8, 0.0), (0.2, 0.0, 0.0), (0.0, 0.3, 0.0), k, 3 * k, const("white_paint"), zen)
    box_side(m, "wing_my", (-0.5, -2.8, 0.0), sx(X), (0.0, 2.0, 0.0), nx, wing_span_cells, const("solar_cell"), zen)
    return m


def check(mesh):
    """Fails loudly unless the mesh has the properties the README promises: no T-junction
    (no vertex inside another edge), and body + boom + instrument one closed surface with
    consistent orientation (each of its edges used once in each direction)."""
    closed = {"body_px", "body_mx", "body_py", "body_my", "body_pz", "body_mz", "boom", "instrument"}
    directed = {}
    edges = set()
    for node, _, tri in mesh.faces:
        for e in range(3):
            a, b = tri[e], tri[(e + 1) % 3]
            edges.add((min(a, b), max(a, b)))
            if node in closed:
                if (a, b) in directed:
                    raise SystemExit("edge %d-%d used twice in one direction" % (a, b))
                directed[(a, b)] = node
    for a, b in directed:
        if (b, a) not in directed:
            raise SystemExit("closed surface has a boundary edge %d-%d" % (a, b))
    cell = 0.05
    buckets = {}
    for i, p in enumerate(mesh.vertices):
        buckets.setdefault(tuple(math.floor(c / cell) for c in p), []).append(i)
    for a, b in sorted(edges):
        pa, pb = mesh.vertices[a], mesh.vertices[b]
        d = [q - p for p, q in zip(pa, pb)]
        length2 = sum(x * x for x in d)
        lo = [math.floor(min(p, q) / cell) for p, q in zip(pa, pb)]
        hi = [math.floor(max(p, q) / cell) for p, q in zip(pa, pb)]
        for cx in range(lo[0], hi[0] + 1):
            for cy in range(lo[1], hi[1] + 1):
                for cz in range(lo[2], hi[2] + 1):
                    for v in buckets.get((cx, cy, cz), ()):
                        if v in (a, b):
                            continue
                        w = [q - p for p, q in zip(pa, mesh.vertices[v])]
                        t = sum(x * y for x, y in zip(w, d)) / length2
                        off = sum((x - t * y) ** 2 for x, y in zip(w, d))
                        if 1e-9 < t < 1 - 1e-9 and off < 1e-18:
                            raise SystemExit("T-junction: vertex %d inside edge %d-%d" % (v, a, b))


NODE_ORDER = ["body_px", "body_mx", "body_py", "body_my", "body_pz", "body_mz",
              "yoke_py", "wing_py", "yoke_my", "wing_my", "boom", "dish", "instrument"]


def write_obj(mesh, path, title):
    lines = ["# " + title,
             "# generated by generate_satellite.py; units: m; groups = thermal nodes, usemtl = coatings",
             "mtllib satellite.mtl"]
    for v in mesh.vertices:
        lines.append("v %.9g %.9g %.9g" % v)
    for node in NODE_ORDER:
        lines.append("g " + node)
        current = None
        for n, mat, (a, b, c) in mesh.faces:
            if n != node:
                continue
            if mat != current:
                lines.append("usemtl " + mat)
                current = mat
            lines.append("f %d %d %d" % (a + 1, b + 1, c + 1))
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def write_mtl(path):
    lines = ["# display colours of thermodec's sample satellite (thermal properties: model.json)"]
    for name in sorted(COLOURS):
        lines += ["newmtl " + name, "Kd %.2f %.2f %.2f" % COLOURS[name], ""]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines))


def model(mesh_file):
    """Thermal model: capacitances from panel masses (aluminium honeycomb ~4-6 kg per body
    panel, c_p ~ 900 J/(kg K), plus mounted units), dissipation of the units mounted on each
    panel, conductive links through brackets, hinges and the boom's interface."""
    def body(material, capacitance, power):
        return {"material": material, "capacitance": capacitance, "power": power}

    nodes = {
        "body_px": body("mli_kapton", 6000.0, 20.0),
        "body_mx": body("mli_kapton", 6000.0, 20.0),
        "body_py": body("mli_kapton", 8000.0, 40.0),
        "body_my": body("osr", 9000.0, 80.0),  # radiator panel: frame faces are white paint
        "body_pz": body("white_paint", 7000.0, 15.0),
        "body_mz": body("mli_kapton", 5000.0, 10.0),
        "yoke_py": {"material": "white_paint", "capacitance": 900.0, "power": 0.0,
                    "two_sided": True, "back_material": "white_paint"},
        "wing_py": {"material": "solar_cell", "capacitance": 4500.0, "power": 0.0,
                    "two_sided": True, "back_material": "white_paint"},
        "yoke_my": {"material": "white_paint", "capacitance": 900.0, "power": 0.0,
                    "two_sided": True, "back_material": "white_paint"},
        "wing_my": {"material": "solar_cell", "capacitance": 4500.0, "power": 0.0,
                    "two_sided": True, "back_material": "white_paint"},
        "boom": body("white_paint", 1300.0, 0.0),
        "dish": {"material": "white_paint", "capacitance": 2000.0, "power": 0.0,
                 "two_sided": True, "back_material": "mli_kapton"},
        "instrument": body("mli_kapton", 8000.0, 25.0),  # aperture faces are black paint
    }
    conductances = []
    # The twelve body edges: panels bolted through corner brackets.
    sides = ["body_px", "body_mx", "body_py", "body_my", "body_pz", "body_mz"]
    opposite = {("body_px", "body_mx"), ("body_py", "body_my"), ("body_pz", "body_mz")}
    for i, a in enumerate(sides):
        for b in sides[i + 1:]:
            if (a, b) not in opposite:
                conductances.append({"from": a, "to": b, "value": 1.0})
    conductances += [
        {"from": "body_py", "to": "yoke_py", "value": 0.5},   # deployment mechanism
        {"from": "yoke_py", "to": "wing_py", "value": 0.3},   # hinge
        {"from": "body_my", "to": "yoke_my", "value": 0.5},
        {"from": "yoke_my", "to": "wing_my", "value": 0.3},
        {"from": "body_pz", "to": "boom", "value": 0.8},      # boom foot
        {"from": "boom", "to": "dish", "value": 0.2},         # dish hub, isolating washers
        {"from": "body_pz", "to": "instrument", "value": 1.5},  # instrument mounting feet
    ]
    return {
        "mesh": mesh_file,
        "unit_scale": 1.0,
        "materials": MATERIALS,
        "default_material": "white_paint",
        "nodes": nodes,
        "conductances": conductances,
        # Sun-synchronous noon/midnight orbit: at the June solstice (day 172, sun at right
        # ascension 90 deg) an ascending node at 90 deg puts the sun almost in the orbit plane
        # (beta ~ -3 deg), so the craft goes through a ~35 min eclipse every orbit.
        "environment": {"type": "orbit", "altitude_km": 700.0, "inclination_deg": 98.0,
                        "raan_deg": 90.0, "day_of_year": 172, "attitude": "nadir",
                        "albedo": 0.30, "earth_ir_flux": 237.0},
        "analysis": {"type": "transient_orbit", "steps_per_orbit": 60, "orbits": 3},
        "radiation": {"rays_per_face": 4000, "seed": 1},
    }


def write_json(data, path):
    with open(path, "w", newline="\n") as f:
        f.write(json.dumps(data, indent=2) + "\n")


def write_refined(k, out):
    os.makedirs(out, exist_ok=True)
    write_mtl(os.path.join(out, "satellite.mtl"))
    mesh = build(k, 10 * k, 32 * k)
    check(mesh)
    mesh_file = "satellite_k%d.obj" % k
    write_obj(mesh, os.path.join(out, mesh_file),
              "thermodec sample satellite refined %dx: %d vertices, %d triangles"
              % (k, len(mesh.vertices), len(mesh.faces)))
    write_json(model(mesh_file), os.path.join(out, "model_k%d.json" % k))
    print("%s: %d vertices, %d triangles, %d nodes" % (mesh_file, len(mesh.vertices), len(mesh.faces),
                                                       len(NODE_ORDER)))


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--refine" and sys.argv[2].isdigit() and int(sys.argv[2]) >= 1:
        write_refined(int(sys.argv[2]), sys.argv[3])
        return
    if len(sys.argv) > 2 or (len(sys.argv) == 2 and sys.argv[1].startswith("-")):
        sys.exit("usage: generate_satellite.py [OUTPUT_DIR] | --refine K OUTPUT_DIR")
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    write_mtl(os.path.join(out, "satellite.mtl"))
    # The coarse craft is meshed unevenly, as CAD tessellations are: flat wings finely (0.1 m
    # along the span), the dish coarsely (3 rings x 16 segments). Its nodes therefore differ
    # in how far decimation can take them, which is what the reduction driver exploits.
    variants = [("satellite.obj", "model.json", build(1, 3, 16, 20), "coarse"),
                ("satellite_dense.obj", "model_dense.json", build(4, 40, 128), "dense")]
    for mesh_file, model_file, mesh, label in variants:
        check(mesh)
        write_obj(mesh, os.path.join(out, mesh_file),
                  "thermodec sample satellite (%s): %d vertices, %d triangles"
                  % (label, len(mesh.vertices), len(mesh.faces)))
        write_json(model(mesh_file), os.path.join(out, model_file))
        print("%s: %d vertices, %d triangles, %d nodes" % (mesh_file, len(mesh.vertices),
                                                           len(mesh.faces), len(NODE_ORDER)))


if __name__ == "__main__":
    main()
