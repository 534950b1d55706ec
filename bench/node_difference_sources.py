"""What moves one node's temperature between a reference and a reduced model, linearised on the
reference's steady radiative network (docs/benchmarks.md, "Reflected sunlight").

Steady, orbit-averaged: sigma K u = Q with u = T^4, K = diag(sum_j GR_ij + GR_i,space) - GR
(GR from `thermodec viewfactors --json`, radiative_couplings_m2 and to_space_couplings_m2) and Q
the nodes' orbit-mean absorbed loads (`thermodec simulate --json`, loads_W). To first order
    dT_t = e_t^T (sigma K)^-1 (dQ - sigma dK u) / (4 T_t^3),
so the target's difference splits exactly into each load component's change (solar, albedo,
Earth IR, reflected sunlight) and the couplings' change (to space, between nodes), per node.

    python3 bench/node_difference_sources.py REF.json REF_VF.json RED.json RED_VF.json [NODE]

NODE defaults to the node of the largest |dT|. Needs numpy.
"""
import json
import sys

import numpy as np

SIGMA = 5.670374419e-8
PARTS = ["solar", "albedo", "earth_ir", "reflected_solar", "total_external"]


def main(ref_sim, ref_vf, red_sim, red_vf, target=None):
    sr, sd = json.load(open(ref_sim)), json.load(open(red_sim))
    vr, vd = json.load(open(ref_vf)), json.load(open(red_vf))
    names = vr["nodes"]
    if names != vd["nodes"]:
        sys.exit("the two models have different nodes")

    def loads(s, part):
        return np.array([np.mean(s["loads_W"][n][part]) for n in names])

    def temps(s):
        return np.array([np.mean(s["temperatures_K"][n]) for n in names])

    def network(v):
        gr = np.array(v["radiative_couplings_m2"], dtype=float)
        np.fill_diagonal(gr, 0.0)
        space = np.array(v["to_space_couplings_m2"], dtype=float)
        return np.diag(gr.sum(1) + space) - gr, space

    t_ref, t_red = temps(sr), temps(sd)
    k_ref, s_ref = network(vr)
    k_red, s_red = network(vd)
    dt = t_red - t_ref
    t = int(np.argmax(np.abs(dt))) if target is None else names.index(target)
    row = np.linalg.inv(SIGMA * k_ref)[t] / (4 * t_ref[t] ** 3)  # dT_t / dQ_j [K/W]
    u = t_ref ** 4
    print(f"{names[t]}: T {t_ref[t]:.3f} K, dT {dt[t]:+.4f} K (simulate)")
    for part in PARTS:
        dq = loads(sd, part) - loads(sr, part)
        print(f"  {part:16s} {row @ dq:+.4f} K   (sum of changes {dq.sum():+.1f} W, "
              f"{names[t]}'s own {dq[t]:+.1f} W)")
    dk = k_red - k_ref
    couplings = -row @ (SIGMA * dk @ u)
    space = -row @ (SIGMA * (s_red - s_ref) * u)
    print(f"  couplings        {couplings:+.4f} K   (to space {space:+.4f} K, between nodes {couplings - space:+.4f} K)")
    total = row @ (loads(sd, "total_external") - loads(sr, "total_external")) + couplings
    print(f"  linearised total {total:+.4f} K")


if __name__ == "__main__":
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    main(*sys.argv[1:6])
