#!/usr/bin/env python3
"""Checks a triangle PLY written by meshlabserver (-m fq [fc]): face count, per-face quality
holding node ids, one colour per node. Exit 0 when every requested check holds, else 1 with the
reason on stderr. PLY ascii and binary_little_endian; triangles only (what MeshLab writes here).

  check_ply.py OUT.ply [--faces N] [--min-faces N] [--max-faces N] [--nodes N | --max-nodes N] [--faces-per-node N]
               [--integer-quality] [--colour-per-node] [--quality-range LO HI] [--ramp-from-log LOG]

--ramp-from-log: the "colour ramp LO K (blue, node A) .. HI K (red, node B)" line of a
Thermal: simulate log must give the quality's min and max, and the faces must be coloured by
quality (one colour per value, the coldest blue, the hottest red).
"""
import argparse
import re
import sys

import numpy as np

PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def read_ply(path):
    """Returns {element name: structured numpy array}; face lists become a 'vertex_indices'
    field of shape (3,) after checking every face is a triangle."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, elements = None, []
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: header without end_header")
            words = line.decode("ascii").split()
            if not words or words[0] in ("comment", "obj_info"):
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                elements.append((words[1], int(words[2]), []))
            elif words[0] == "property":
                if words[1] == "list":
                    elements[-1][2].append((words[4], "list", PLY_TYPES[words[2]], PLY_TYPES[words[3]]))
                else:
                    elements[-1][2].append((words[2], "scalar", PLY_TYPES[words[1]], None))
            elif words[0] == "end_header":
                break
        body = f.read()

    out = {}
    if fmt == "binary_little_endian":
        offset = 0
        for name, count, props in elements:
            fields = []
            for pname, kind, t, t2 in props:
                if kind == "list":
                    fields.append((pname + "_count", "<" + t))
                    fields.append((pname, "<" + t2, (3,)))
                else:
                    fields.append((pname, "<" + t))
            dtype = np.dtype(fields)
            arr = np.frombuffer(body, dtype=dtype, count=count, offset=offset)
            offset += dtype.itemsize * count
            for pname, kind, _, _ in props:
                if kind == "list" and np.any(arr[pname + "_count"] != 3):
                    raise ValueError(f"{path}: element {name} has non-triangle faces")
            out[name] = arr
    elif fmt == "ascii":
        lines = body.decode("ascii").split("\n")
        pos = 0
        for name, count, props in elements:
            rows = [lines[pos + i].split() for i in range(count)]
            pos += count
            fields, cols = [], []
            for pname, kind, t, t2 in props:
                if kind == "list":
                    fields.append((pname, t2, (3,)))
                else:
                    fields.append((pname, t))
            arr = np.zeros(count, dtype=np.dtype(fields))
            for i, r in enumerate(rows):
                k = 0
                for pname, kind, _, _ in props:
                    if kind == "list":
                        if int(r[k]) != 3:
                            raise ValueError(f"{path}: face {i} is not a triangle")
                        arr[pname][i] = [float(x) for x in r[k + 1:k + 4]]
                        k += 4
                    else:
                        arr[pname][i] = float(r[k])
                        k += 1
            out[name] = arr
    else:
        raise ValueError(f"{path}: unsupported PLY format {fmt}")
    return out


def check_ramp(faces, q, log_path, fail):
    with open(log_path, encoding="utf-8", errors="replace") as f:
        m = re.search(r"colour ramp ([0-9.]+) K \(blue, node ([^)]+)\) \.\. ([0-9.]+) K \(red, node ([^)]+)\)", f.read())
    if not m:
        fail(f"no colour ramp line in {log_path}")
    lo, hi = float(m.group(1)), float(m.group(3))
    # The log prints two decimals; the PLY holds float32 kelvin.
    if abs(q.min() - lo) > 0.006 or abs(q.max() - hi) > 0.006:
        fail(f"quality [{q.min():.3f}, {q.max():.3f}] is not the logged ramp [{lo:.2f}, {hi:.2f}]")
    if "red" not in faces.dtype.names:
        fail("faces have no colour (saved without -m fc?)")
    rgb = np.stack([faces["red"], faces["green"], faces["blue"]], axis=1).astype(np.int64)
    key = rgb[:, 0] * 65536 + rgb[:, 1] * 256 + rgb[:, 2]
    for value in np.unique(q):
        if len(np.unique(key[q == value])) != 1:
            fail(f"faces at {value:g} K have several colours: not coloured by quality")
    cold, hot = rgb[np.argmin(q)], rgb[np.argmax(q)]
    if not (cold[2] > cold[0] and hot[0] > hot[2]):
        fail(f"coldest face colour {cold.tolist()} is not blue or hottest {hot.tolist()} not red")
    print(f"  colour ramp {lo:.2f} K ({m.group(2)}, rgb {cold.tolist()}) .. {hi:.2f} K ({m.group(4)}, rgb {hot.tolist()})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ply")
    ap.add_argument("--faces", type=int)
    ap.add_argument("--min-faces", type=int)
    ap.add_argument("--max-faces", type=int)
    ap.add_argument("--nodes", type=int)
    ap.add_argument("--max-nodes", type=int)
    ap.add_argument("--faces-per-node", type=int)
    ap.add_argument("--integer-quality", action="store_true")
    ap.add_argument("--colour-per-node", action="store_true")
    ap.add_argument("--quality-range", type=float, nargs=2)
    ap.add_argument("--ramp-from-log")
    a = ap.parse_args()

    def fail(msg):
        print(f"check_ply: {a.ply}: {msg}", file=sys.stderr)
        sys.exit(1)

    ply = read_ply(a.ply)
    faces = ply.get("face")
    if faces is None:
        fail("no face element")
    n = len(faces)
    print(f"{a.ply}: {n} faces")
    if a.faces is not None and n != a.faces:
        fail(f"{n} faces, expected {a.faces}")
    if a.min_faces is not None and n < a.min_faces:
        fail(f"{n} faces, expected at least {a.min_faces}")
    if a.max_faces is not None and n > a.max_faces:
        fail(f"{n} faces, expected at most {a.max_faces}")
    names = faces.dtype.names
    need_q = a.nodes or a.max_nodes or a.faces_per_node or a.integer_quality or a.colour_per_node or a.quality_range \
        or a.ramp_from_log
    if need_q and "quality" not in names:
        fail("faces have no quality (saved without -m fq?)")
    if not need_q:
        return
    q = faces["quality"].astype(np.float64)
    print(f"  quality in [{q.min():g}, {q.max():g}]")
    if a.quality_range and (q.min() < a.quality_range[0] or q.max() > a.quality_range[1]):
        fail(f"quality [{q.min():g}, {q.max():g}] outside [{a.quality_range[0]:g}, {a.quality_range[1]:g}]")
    if a.ramp_from_log:
        check_ramp(faces, q, a.ramp_from_log, fail)
    if a.integer_quality or a.nodes or a.max_nodes or a.faces_per_node or a.colour_per_node:
        bad = np.nonzero((q != np.floor(q)) | (q < 0))[0]
        if len(bad):
            fail(f"face {bad[0]} quality {q[bad[0]]:g} is not a node id")
    ids, counts = np.unique(q.astype(np.int64), return_counts=True)
    print(f"  {len(ids)} distinct node ids, faces per node {counts.min()}..{counts.max()}")
    if a.nodes is not None and len(ids) != a.nodes:
        fail(f"{len(ids)} nodes, expected {a.nodes}")
    if a.max_nodes is not None and len(ids) > a.max_nodes:
        fail(f"{len(ids)} nodes, more than {a.max_nodes}")
    if a.faces_per_node is not None and np.any(counts != a.faces_per_node):
        fail(f"faces per node {counts.tolist()}, expected {a.faces_per_node} each")
    if a.colour_per_node:
        if "red" not in names:
            fail("faces have no colour (saved without -m fc?)")
        rgb = np.stack([faces["red"], faces["green"], faces["blue"]], axis=1).astype(np.int64)
        key = rgb[:, 0] * 65536 + rgb[:, 1] * 256 + rgb[:, 2]
        for i in ids:
            if len(np.unique(key[q == i])) != 1:
                fail(f"node {i} has several colours")
        if len(np.unique(key)) != len(ids):
            fail(f"{len(np.unique(key))} colours for {len(ids)} nodes")


if __name__ == "__main__":
    main()
