#!/usr/bin/env python3
"""Checks the five files of "Thermal: export for other tools" (export_model.mlx.in) against the
model they came from, with readers that do not share the writers' code:

    check_export.py THERMODEC MODEL.json OUTDIR STEM

- model.bdf: `thermodec info` reports the same faces, vertices, total area and, per node, the
  same faces and area as for MODEL (the plugin's mesh went through MeshLab's float coordinates:
  the printed 4-5 significant digits are unaffected);
- model.d (ESATAN-TMS): one D/A/B node entry per model node plus deep space, labelled with the
  model's node names, and the $ENDMODEL line;
- model.inp (SINDA/FLUINT): one NODE DATA line per model node plus deep space;
- vtk/STEM.pvd: every data set it lists exists and has one cell per face;
- model_*.csv: a temperature column per node, the coupling table's header.
"""
import re
import subprocess
import sys
from pathlib import Path


def fail(msg):
    print("FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


def info(thermodec, path):
    out = subprocess.run([thermodec, "info", str(path)], capture_output=True, text=True)
    if out.returncode != 0:
        fail(f"thermodec info {path}: {out.stderr.strip()}")
    summary, nodes, in_nodes = {}, {}, False
    for line in out.stdout.splitlines():
        for key in ("faces", "vertices", "area"):
            if line.startswith(key + " "):
                summary[key] = line.split()[1]
        if line.startswith("nodes"):
            in_nodes = True
            continue
        fields = line.split()
        if in_nodes and line.startswith("  ") and len(fields) >= 3 and fields[0] != "node":
            nodes[fields[0]] = (fields[1], fields[2])  # faces, area [m^2]
    return summary, nodes


def main():
    thermodec, model, outdir, stem = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3]), sys.argv[4]
    ref_summary, ref_nodes = info(thermodec, model)
    if not ref_nodes:
        fail(f"no nodes read from `thermodec info {model}`")

    summary, nodes = info(thermodec, outdir / "model.bdf")
    if summary != ref_summary:
        fail(f"model.bdf: {summary} != {ref_summary}")
    if nodes != ref_nodes:
        fail(f"model.bdf nodes (faces, area): {nodes} != {ref_nodes}")
    print(f"model.bdf: {summary['faces']} faces, {summary['vertices']} vertices, area {summary['area']} m^2, "
          f"{len(nodes)} nodes with their faces and areas, as {model.name}")

    esatan = (outdir / "model.d").read_text()
    labels = re.findall(r"^[DAB]\d+ = '([^']*)'", esatan, re.M)
    if sorted(labels) != sorted(list(ref_nodes) + ["deep space"]):
        fail(f"model.d node labels {labels}")
    if not re.search(r"^\$ENDMODEL", esatan, re.M):
        fail("model.d has no $ENDMODEL")
    print(f"model.d: {len(labels)} nodes (with deep space)")

    sinda = (outdir / "model.inp").read_text()
    block = re.search(r"^HEADER NODE DATA.*?\n(.*?)^HEADER", sinda, re.M | re.S)
    lines = [l for l in block.group(1).splitlines() if l.strip() and not l.startswith("C")] if block else []
    if len(lines) != len(ref_nodes) + 1:
        fail(f"model.inp: {len(lines)} NODE DATA lines for {len(ref_nodes)} nodes + deep space")
    print(f"model.inp: {len(lines)} nodes (with deep space)")

    pvd = outdir / "vtk" / (stem + ".pvd")
    files = re.findall(r'file="([^"]+)"', pvd.read_text())
    if not files:
        fail(f"{pvd} lists no data set")
    for f in files:
        vtu = (pvd.parent / f).read_text()
        if f'NumberOfCells="{ref_summary["faces"]}"' not in vtu:
            fail(f"{f} does not have {ref_summary['faces']} cells")
    print(f"{pvd.name}: {len(files)} steps of {ref_summary['faces']} cells")

    header = (outdir / "model_temperatures.csv").read_text().splitlines()[0].split(",")
    if header[0] != "time_s" or sorted(header[1:]) != sorted(ref_nodes):
        fail(f"model_temperatures.csv header {header}")
    if (outdir / "model_couplings.csv").read_text().splitlines()[0] != "from,to,type,value,unit":
        fail("model_couplings.csv header")
    print(f"model_temperatures.csv: {len(header) - 1} nodes")


if __name__ == "__main__":
    main()
