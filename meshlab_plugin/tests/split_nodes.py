#!/usr/bin/env python3
"""Splits a PLY written by `thermodec convert` (node id in float face quality, names in
`comment thermodec node <id> <name>` lines) into one PLY per node plus a MeshLab project
listing them: the paper's one-file-per-cluster layout, for the multi-layer tests.

  split_nodes.py IN.ply OUTDIR      -> OUTDIR/<node>.ply ..., OUTDIR/nodes.mlp
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_ply import read_ply  # noqa: E402


def node_names(path):
    names = {}
    with open(path, "rb") as f:
        for raw in f:
            words = raw.decode("ascii", "replace").split()
            if words and words[0] == "end_header":
                break
            if words[:3] == ["comment", "thermodec", "node"] and len(words) >= 5:
                names[int(words[3])] = words[4]
    return names


def main():
    src, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    ply = read_ply(src)
    v = ply["vertex"]
    f = ply["face"]
    xyz = np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float64)
    node = f["quality"].astype(np.int64)
    names = node_names(src)
    layers = []
    for n in np.unique(node):
        name = names.get(int(n), f"node_{n:03d}")
        tri = f["vertex_indices"][node == n]
        used, inverse = np.unique(tri.ravel(), return_inverse=True)
        tri = inverse.reshape(-1, 3)
        path = os.path.join(out, name + ".ply")
        with open(path, "w") as o:
            o.write("ply\nformat ascii 1.0\n")
            o.write(f"comment node {name} of {os.path.basename(src)}\n")
            o.write(f"element vertex {len(used)}\nproperty double x\nproperty double y\nproperty double z\n")
            o.write(f"element face {len(tri)}\nproperty list uchar int vertex_indices\nend_header\n")
            for p in xyz[used]:
                o.write("%.9g %.9g %.9g\n" % tuple(p))
            for t in tri:
                o.write("3 %d %d %d\n" % tuple(t))
        layers.append((name, path))
    with open(os.path.join(out, "nodes.mlp"), "w") as o:
        o.write("<!DOCTYPE MeshLabDocument>\n<MeshLabProject>\n <MeshGroup>\n")
        for name, path in layers:
            o.write(f'  <MLMesh label="{name}.ply" filename="{os.path.abspath(path)}" visible="1">\n')
            o.write("   <MLMatrix44>\n1 0 0 0 \n0 1 0 0 \n0 0 1 0 \n0 0 0 1 \n</MLMatrix44>\n  </MLMesh>\n")
        o.write(" </MeshGroup>\n <RasterGroup/>\n</MeshLabProject>\n")
    print(f"{src}: {len(layers)} node files in {out}")


if __name__ == "__main__":
    main()
