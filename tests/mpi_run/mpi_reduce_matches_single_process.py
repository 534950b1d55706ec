"""`mpirun -np 2 thermodec reduce` gives the single-process result bit for bit (sample satellite).

Usage: mpi_reduce_matches_single_process.py THERMODEC MODEL_JSON WORKDIR
Skips (exit 77) when mpirun is absent. Compares reduced.obj, model.json and report.json without
its timings, peak memory and MPI block.
"""
import json, shutil, subprocess, sys, pathlib

exe, model, work = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
mpirun = shutil.which("mpirun")
if not mpirun:
    print("SKIP: mpirun not found (apt-get install openmpi-bin)")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
args = ["reduce", model, "--no-plots", "-q", "-o"]
subprocess.run([exe] + args + [str(work / "one")], check=True)
subprocess.run([mpirun, "-np", "2", "--oversubscribe", "--bind-to", "none", exe] + args + [str(work / "two")], check=True)
for f in ["reduced.obj", "model.json"]:
    if (work / "one" / f).read_bytes() != (work / "two" / f).read_bytes():
        sys.exit(f"{f} differs between 1 and 2 MPI ranks")
a, b = (json.loads((work / d / "report.json").read_text()) for d in ("one", "two"))
if b.get("mpi", {}).get("ranks") != 2:
    sys.exit("the 2-rank report does not say it ran on 2 ranks")
for r in (a, b):
    for k in ("timings_s", "peak_memory_bytes", "mpi"):
        r.pop(k, None)
if a != b:
    sys.exit("report.json differs between 1 and 2 MPI ranks")
print("2 MPI ranks: reduced.obj, model.json and report.json identical to one process")
