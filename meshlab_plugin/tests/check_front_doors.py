#!/usr/bin/env python3
"""The four front doors give one simulation: `thermodec simulate --json`, the Python module's
simulate_model (what FreeCAD calls), `thermodec export` (its CSV temperatures) and MeshLab's
"Thermal: simulate" run by meshlabserver (its result file) on the sample satellite with the
same model file and seed must give bit-identical temperatures, and MeshLab must log the CLI's
temperature range.

  check_front_doors.py THERMODEC MESHLABSERVER MODEL.json MESH.ply WORKDIR

MESH.ply is the model's mesh as MeshLab opens it (`thermodec convert MODEL.json MESH.ply`).
The module `thermodec` must be importable (PYTHONPATH)."""
import json
import os
import re
import subprocess
import sys

import numpy as np

import thermodec as td

# One X server per run (the repository's scripts/with_xvfb): parallel tests never share a display.
WITH_XVFB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "with_xvfb")


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def temperatures(result):
    """nodes x times [K] of a result JSON (docs/thermal.md, "Result file")."""
    return np.array([result["temperatures_K"][n] for n in result["nodes"]], dtype=float)


def main(cli, server, model_file, mesh, work):
    os.makedirs(work, exist_ok=True)
    seed = 1
    # 1. The CLI.
    cli_json = os.path.join(work, "cli.json")
    out = subprocess.run([cli, "simulate", model_file, "--json", cli_json, "--seed", str(seed)],
                         capture_output=True, text=True)
    if out.returncode != 0:
        fail("thermodec simulate failed:\n" + out.stderr)
    with open(cli_json) as f:
        ref = json.load(f)
    nodes = ref["nodes"]
    T_cli = temperatures(ref)
    print("CLI: %d nodes x %d times, %.17g .. %.17g K" % (T_cli.shape[0], T_cli.shape[1], T_cli.min(), T_cli.max()))

    # 2. The Python module.
    r = td.simulate_model(td.load_model(model_file), seed=seed)
    T_py = np.asarray(r.temperature_K)
    if list(r.nodes) != nodes or T_py.shape != T_cli.shape or not np.array_equal(T_py, T_cli):
        fail("the Python module's temperatures differ from the CLI's (max |dT| %s K)"
             % (np.abs(T_py - T_cli).max() if T_py.shape == T_cli.shape else "shape"))
    print("Python module: bit-identical")

    # 3. MeshLab (meshlabserver), with the result file.
    ml_json = os.path.join(work, "meshlab.json")
    script = os.path.join(work, "simulate.mlx")
    with open(script, "w") as f:
        f.write('<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name="Thermal: simulate">\n'
                f'  <Param type="RichString" name="model_file" value="{model_file}" description="m" tooltip="m"/>\n'
                '  <Param type="RichInt" name="rays_per_face" value="0" description="r" tooltip="r"/>\n'
                '  <Param type="RichEnum" name="face_value" value="1" enum_cardinality="3" enum_val0="min" '
                'enum_val1="mean" enum_val2="max" description="f" tooltip="f"/>\n'
                f'  <Param type="RichInt" name="seed" value="{seed}" description="s" tooltip="s"/>\n'
                f'  <Param type="RichString" name="result_file" value="{ml_json}" description="r" tooltip="r"/>\n'
                ' </filter>\n</FilterScript>\n')
    if os.path.exists(ml_json):
        os.remove(ml_json)
    out = subprocess.run([WITH_XVFB, server, "-i", mesh, "-o", os.path.join(work, "meshlab.ply"),
                          "-m", "fq", "fc", "-s", script], capture_output=True, text=True, cwd=work)
    log = out.stdout + out.stderr
    with open(os.path.join(work, "meshlab.log"), "w") as f:
        f.write(log)
    if out.returncode != 0 or not os.path.exists(ml_json):
        fail("meshlabserver failed (exit %d):\n%s" % (out.returncode, log[-3000:]))
    with open(ml_json) as f:
        ml = json.load(f)
    T_ml = temperatures(ml)
    if ml["nodes"] != nodes or T_ml.shape != T_cli.shape or not np.array_equal(T_ml, T_cli):
        fail("MeshLab's temperatures differ from the CLI's (max |dT| %s K)"
             % (np.abs(T_ml - T_cli).max() if T_ml.shape == T_cli.shape else "shape"))
    print("MeshLab: bit-identical")
    # ...and the range MeshLab logs is the CLI's (two decimals, as both print it).
    m = re.search(r"temperature range over the orbit: ([0-9.]+) K .*\.\. ([0-9.]+) K", log)
    want = ("%.2f" % T_cli.min(), "%.2f" % T_cli.max())
    if not m or m.groups() != want:
        fail("MeshLab logs the range %s, the CLI's is %s .. %s K" % (m.groups() if m else None, *want))
    print("MeshLab logs the CLI's range: %s .. %s K" % want)

    # 4. `thermodec export` (CSV temperatures, the same simulation).
    prefix = os.path.join(work, "export")
    out = subprocess.run([cli, "export", model_file, "-f", "csv", "-o", prefix, "-q"], capture_output=True, text=True)
    if out.returncode != 0:
        fail("thermodec export failed:\n" + out.stderr)
    T_csv = np.loadtxt(prefix + "_temperatures.csv", delimiter=",", skiprows=1, ndmin=2)[:, 1:].T
    if T_csv.shape != T_cli.shape or not np.array_equal(T_csv, T_cli):  # shortest round-trip decimals
        fail("export's temperatures differ from the CLI's (max |dT| %s K)"
             % (np.abs(T_csv - T_cli).max() if T_csv.shape == T_cli.shape else "shape"))
    print("export: bit-identical")

if __name__ == "__main__":
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    main(*sys.argv[1:])
