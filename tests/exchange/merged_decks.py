"""A merged model's exported decks hold the merged network: `thermodec merge` joins nodes of the
sample, the ESATAN and SINDA decks of the merged model list exactly the merged node count (plus the
space node), and deck_round_trip.py integrates them from the files alone to `simulate`'s
temperatures of the merged model; `compare` reads the merged result through its node map.

usage: merged_decks.py THERMODEC MODEL WORKDIR
Exit 77 (CTest SKIP_RETURN_CODE) when deck_round_trip.py skips (numpy or scipy missing).
"""
import json
import os
import re
import subprocess
import sys

thermodec, model, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
here = os.path.dirname(os.path.abspath(__file__))
FAST = ["--rays", "400", "--noise-target", "0", "-q"]


def run(*args):
    r = subprocess.run([thermodec, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("thermodec %s failed: %s" % (" ".join(args), r.stderr))
    return r.stdout


merged = os.path.join(work, "merged.json")
run("merge", model, "--group", "body_px,body_py,body_pz", "--group", "yoke_*,wing_*", "-o", merged)
m = json.load(open(merged))
original = json.load(open(model))
n_merged, n_original = len(m["nodes"]), len(original["nodes"])
print("merged model: %d -> %d nodes" % (n_original, n_merged))
failures = []
if sorted(m["node_map"]) != sorted(original["nodes"]):
    failures.append("node_map does not list every original node")
if sorted(set(m["node_map"].values())) != sorted(m["nodes"]):
    failures.append("node_map does not map onto the merged nodes")

rt = os.path.join(work, "round_trip")
r = subprocess.run([sys.executable, os.path.join(here, "deck_round_trip.py"), thermodec, merged, rt],
                   capture_output=True, text=True)
print(r.stdout, end="")
if r.returncode == 77:
    sys.exit(77)
if r.returncode != 0:
    failures.append("deck round trip of the merged model failed: " + r.stdout[-400:] + r.stderr[-400:])
else:
    esatan = open(os.path.join(rt, "sat.d")).read()
    ids = {int(n) for n in re.findall(r"^[DAB](\d+) = '", esatan, re.M)} - {99999}
    sinda = open(os.path.join(rt, "sat.inp")).read()
    block = re.search(r"^HEADER NODE DATA[^\n]*\n(.*?)(?=^HEADER )", sinda, re.M | re.S).group(1)
    sinda_ids = {abs(int(float(l.split("$")[0].split(",")[0]))) for l in block.splitlines()
                 if l.split("$")[0].strip()} - {99999}
    print("ESATAN deck: %d nodes, SINDA deck: %d nodes" % (len(ids), len(sinda_ids)))
    for what, k in (("ESATAN", len(ids)), ("SINDA", len(sinda_ids))):
        if k != n_merged:
            failures.append("%s deck holds %d nodes, the merged model %d" % (what, k, n_merged))

# compare: the original's result against the merged one's, node by node through the map.
a, b = os.path.join(work, "original.json"), os.path.join(work, "merged_result.json")
run("simulate", model, "--json", a, *FAST)
run("simulate", merged, "--json", b, *FAST)
out = json.loads(run("compare", a, b, "--json"))
if len(out["nodes"]) != n_original:
    failures.append("compare lists %d nodes, the original has %d" % (len(out["nodes"]), n_original))
print("compare original vs merged through the node map: max |dT| = %.3f K at %s" % (out["max_abs_dT_K"], out["node"]))

if failures:
    print("\n".join("FAIL: " + f for f in failures))
    sys.exit(1)
print("the merged model's decks hold its %d nodes and reproduce simulate" % n_merged)
