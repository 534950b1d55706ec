"""Coverage of `summary.<node>.noise_K`: each node's spread over fresh seeds against its stated
one-sigma sampling noise. One line per node (spread = largest |T_a - T_b| over every pair of runs
and every position), then the two figures that decide whether the error bars hold: the largest
spread / noise_K (understated if over 6 for 4 runs) and the median over nodes of noise_K /
spread (padded if over 5).

usage: noise_coverage.py THERMODEC MODEL SEED... (e.g. 11 12 13 14)
       noise_coverage.py --results A.json B.json ...   (results already simulated)
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

if sys.argv[1] == "--results":
    paths = sys.argv[2:]
else:
    thermodec, model, seeds = sys.argv[1], sys.argv[2], sys.argv[3:]
    work = tempfile.mkdtemp(prefix="noise_coverage_")
    paths = []
    for seed in seeds:
        paths.append(os.path.join(work, "seed%s.json" % seed))
        subprocess.run([thermodec, "simulate", model, "--seed", seed, "--json", paths[-1], "-q"], check=True)
runs = [json.load(open(p)) for p in paths]
under, over = [], []
print("%-14s %10s %10s %8s" % ("node", "spread K", "noise_K", "ratio"))
for n in runs[0]["nodes"]:
    T = [r["temperatures_K"][n] for r in runs]
    spread = max(abs(T[a][k] - T[b][k]) for a in range(len(T)) for b in range(a + 1, len(T)) for k in range(len(T[0])))
    noise = statistics.mean(r["summary"][n]["noise_K"] for r in runs)
    print("%-14s %10.5f %10.5f %8.2f" % (n, spread, noise, spread / noise))
    under.append(spread / noise)
    over.append(noise / spread if spread > 0 else float("inf"))
print("%d runs: max spread / noise_K = %.2f (<= 6: not understated); median noise_K / spread = %.2f (<= 5: not padded)"
      % (len(runs), max(under), statistics.median(over)))
