"""Lower bound on the node count a merge can reach within a tolerance (docs/reduction.md,
"Merging nodes"). A merged node has one temperature T_m(t); every member i must stay within the
tolerance of it at every time and load case, |T_i(t) - T_m(t)| <= tol, so two members differ by
at most 2 tol at every t. Nodes that differ by more, beyond the sampling noise, must end up in
different merged nodes: any set of pairwise incompatible nodes is a lower bound on the merged
node count, whatever the merges and whatever the merged temperatures. At one time the largest
such set is exact and greedy (sorted temperatures, a new node each time one lies more than
2 tol + margin above the last one taken); over several times the largest per-time set is still a
valid bound. The temperatures are the original's (one `simulate --json`), the margin
k x sqrt(noise_i^2 + noise_j^2) from each node's one-sigma `summary.<node>.noise_K`.

Conductances or fixed nodes change nothing here: the bound only uses temperatures. It ignores
that a merged node's temperature is not free (an area-weighted mean of its members' T^4) and
that merged nodes should touch, so the true minimum can only be higher.

usage: merge_lower_bound.py RESULT.json [--tolerance K] [--sigmas K] [--json]
       (several --tolerance values allowed, e.g. the whole tolerance and the merges' share)
"""
import argparse
import json
import math


def lower_bound(result, tolerance_K, sigmas):
    """(bound, nodes of one largest set) for `result` (a simulate --json dict)."""
    temps = result["temperatures_K"]
    noise = {n: result.get("summary", {}).get(n, {}).get("noise_K", 0.0) or 0.0 for n in temps}
    steps = len(next(iter(temps.values())))
    best = []
    for t in range(steps):
        order = sorted(temps, key=lambda n: temps[n][t])
        taken = []
        for n in order:
            if not taken:
                taken.append(n)
                continue
            last = taken[-1]
            margin = sigmas * math.hypot(noise[n], noise[last])
            if temps[n][t] - temps[last][t] > 2.0 * tolerance_K + margin:
                taken.append(n)
        # Consecutive ones differ by more than 2 tol + their margin; the differences add up
        # along the sorted order (every pair is checked below).
        if len(taken) > len(best):
            best = taken
    for a in range(len(best)):  # every pair, not only neighbours, must be incompatible
        for b in range(a + 1, len(best)):
            gap = max(abs(x - y) for x, y in zip(temps[best[a]], temps[best[b]]))
            assert gap > 2.0 * tolerance_K + sigmas * math.hypot(noise[best[a]], noise[best[b]])
    return len(best), best


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("result")
    p.add_argument("--tolerance", type=float, action="append", help="temperature tolerance [K] (default 0.5)")
    p.add_argument("--sigmas", type=float, default=3.0, help="noise margin in one-sigma noise units (default 3)")
    p.add_argument("--json", action="store_true", help="print JSON")
    a = p.parse_args()
    result = json.load(open(a.result))
    out = []
    for tol in a.tolerance or [0.5]:
        bound, nodes = lower_bound(result, tol, a.sigmas)
        out.append({"tolerance_K": tol, "sigmas": a.sigmas, "nodes": len(result["temperatures_K"]),
                    "min_nodes_lower_bound": bound, "pairwise_incompatible": nodes})
    if a.json:
        print(json.dumps(out, indent=1))
        return
    for o in out:
        print("%s: %d nodes; within %.3g K (margin %.3g sigma) at least %d merged nodes (%.0f %%)" %
              (a.result, o["nodes"], o["tolerance_K"], o["sigmas"], o["min_nodes_lower_bound"],
               100.0 * o["min_nodes_lower_bound"] / o["nodes"]))


if __name__ == "__main__":
    main()
