"""Least merged node count within a tolerance, exact for a free merged temperature
(docs/reduction.md, "Merging nodes"; bench/merge_lower_bound.py gives the per-time bound).

A merged node has one temperature T_m(t); every member i must stay within the tolerance of it,
|T_i(t) - T_m(t)| <= tol at every time and load case. A set of nodes can share one T_m exactly
when its spread max_i T_i(t) - min_i T_i(t) is <= 2 tol at every t, i.e. when every PAIR of its
members differs by <= 2 tol at every t (the spread at t is the largest pairwise difference at t).
So the least number of merged nodes, with each merged temperature free to sit anywhere, is the
least number of cliques covering the compatibility graph, i.e. the chromatic number of the
incompatibility graph (an edge where two nodes differ by more than 2 tol + margin at some t).
Solved exactly as an integer programme (scipy.optimize.milp, HiGHS): x[i,k] node i in merged
node k, y[k] merged node k used, x[i,k] + x[j,k] <= y[k] for every incompatible pair, a largest
incompatible set (found first, also exactly) fixed to distinct merged nodes.

Every physical merge does worse: a merged node's temperature is not free (its members' heat
balance sets it), merged nodes should touch, and the decimation and the verification's
statistical margin take their share of the same tolerance. So a count above the target means no
merge search, however clever, can reach the target within the tolerance.

Temperatures: the mean of one or more `simulate --json` results of the same model with different
seeds; margin k x sigma of the difference of two nodes' means (sigma from each result's
`noise_K`, divided by sqrt(number of results)).

usage: /usr/bin/python3 merge_exact_bound.py RESULT.json [RESULT2.json ...] [--tolerance K ...]
       [--sigmas K] [--json]
"""
import argparse
import json
import math
import sys

import numpy as np
from scipy.optimize import milp, LinearConstraint, Bounds
from scipy.sparse import lil_matrix


def mean_temperatures(results):
    names = list(results[0]["temperatures_K"])
    t = np.array([[r["temperatures_K"][n] for n in names] for r in results])  # runs x nodes x times
    noise = np.array([[(r.get("summary", {}).get(n, {}) or {}).get("noise_K", 0.0) or 0.0 for n in names]
                      for r in results])
    sigma = np.sqrt((noise ** 2).mean(axis=0) / len(results))  # one sigma of each node's mean
    return names, t.mean(axis=0), sigma


def incompatible(temps, sigma, tol, sigmas):
    """Boolean matrix: nodes differing by more than 2 tol + margin at some time."""
    spread = np.abs(temps[:, None, :] - temps[None, :, :]).max(axis=2)
    margin = sigmas * np.hypot(sigma[:, None], sigma[None, :])
    bad = spread > 2.0 * tol + margin
    np.fill_diagonal(bad, False)
    return bad


def largest_incompatible_set(bad):
    """Maximum clique of the incompatibility graph (binary programme)."""
    n = bad.shape[0]
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n) if not bad[i, j]]
    a = lil_matrix((max(len(pairs), 1), n))
    for r, (i, j) in enumerate(pairs):
        a[r, i] = a[r, j] = 1
    res = milp(-np.ones(n), integrality=np.ones(n), bounds=Bounds(0, 1),
               constraints=[LinearConstraint(a.tocsr(), -np.inf, 1)] if pairs else [])
    return [i for i in range(n) if res.x[i] > 0.5]


def least_merged_nodes(bad, clique, time_limit_s):
    """(count, groups, proven optimal) of the least clique cover of the compatibility graph."""
    n = bad.shape[0]
    order = clique + [i for i in range(n) if i not in clique]
    kmax = n
    nv = n * kmax + kmax
    x = lambda i, k: i * kmax + k
    y = lambda k: n * kmax + k
    rows, lo, hi = [], [], []

    def add(coefs, l, h):
        rows.append(coefs)
        lo.append(l)
        hi.append(h)

    for i in range(n):
        add({x(i, k): 1 for k in range(kmax)}, 1, 1)
    for i in range(n):
        for j in range(i + 1, n):
            if bad[i, j]:
                for k in range(kmax):
                    add({x(i, k): 1, x(j, k): 1, y(k): -1}, -np.inf, 0)
    for i in range(n):
        for k in range(kmax):
            add({x(i, k): 1, y(k): -1}, -np.inf, 0)
    for k in range(kmax - 1):  # symmetry: merged nodes used in order
        add({y(k): 1, y(k + 1): -1}, 0, np.inf)
    ub = np.ones(nv)
    lb = np.zeros(nv)
    for pos, i in enumerate(order):  # node order[pos] only in merged nodes 0..pos; the clique fixed
        for k in range(kmax):
            if k > pos:
                ub[x(i, k)] = 0
        if pos < len(clique):
            lb[x(i, pos)] = 1
    a = lil_matrix((len(rows), nv))
    for r, c in enumerate(rows):
        for col, v in c.items():
            a[r, col] = v
    cost = np.zeros(nv)
    cost[n * kmax:] = 1
    res = milp(cost, integrality=np.ones(nv), bounds=Bounds(lb, ub),
               constraints=[LinearConstraint(a.tocsr(), lo, hi)], options={"time_limit": time_limit_s})
    groups = {}
    for i in range(n):
        k = int(np.argmax([res.x[x(i, k)] for k in range(kmax)]))
        groups.setdefault(k, []).append(i)
    proven = res.status == 0
    lower = math.ceil(res.mip_dual_bound - 1e-6) if getattr(res, "mip_dual_bound", None) is not None else None
    return len(groups), list(groups.values()), proven, lower


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("results", nargs="+")
    p.add_argument("--tolerance", type=float, action="append", help="temperature tolerance [K] (default 0.5)")
    p.add_argument("--sigmas", type=float, default=3.0, help="noise margin in one-sigma noise units (default 3)")
    p.add_argument("--time-limit", type=float, default=300.0, help="seconds per integer programme")
    p.add_argument("--json", action="store_true", help="print JSON")
    a = p.parse_args()
    results = [json.load(open(f)) for f in a.results]
    names, temps, sigma = mean_temperatures(results)
    out = []
    for tol in a.tolerance or [0.5]:
        bad = incompatible(temps, sigma, tol, a.sigmas)
        clique = largest_incompatible_set(bad)
        count, groups, proven, lower = least_merged_nodes(bad, clique, a.time_limit)
        out.append({"tolerance_K": tol, "sigmas": a.sigmas, "runs": len(results), "nodes": len(names),
                    "largest_incompatible_set": len(clique), "least_merged_nodes": count, "proven": proven,
                    "lower_bound": lower if lower is not None else len(clique),
                    "groups": [[names[i] for i in g] for g in groups]})
    if a.json:
        json.dump(out, sys.stdout, indent=1)
        print()
        return
    for o in out:
        print("within %.3g K (margin %.3g sigma, %d runs): %d nodes, largest incompatible set %d, "
              "least merged nodes %d%s (%.0f %%)" %
              (o["tolerance_K"], o["sigmas"], o["runs"], o["nodes"], o["largest_incompatible_set"],
               o["least_merged_nodes"], "" if o["proven"] else " (not proven, bound %s)" % o["lower_bound"],
               100.0 * o["least_merged_nodes"] / o["nodes"]))


if __name__ == "__main__":
    main()
