"""Per-node sensitivity curves (paper Fig. 10): max |dT| of the whole model vs the node's
reduction ratio. Input: {"tolerance_K": t, "cap_K": c, "curves": [{"node": name,
"faces_before": n, "ratios": [...], "max_abs_dT_K": [...]}]}"""
from _common import load_args, plt, save

data, out = load_args()
fig, ax = plt.subplots(figsize=(8, 5))
curves = sorted(data["curves"], key=lambda c: c.get("faces_before", 0))
for c in curves:
    r = [0.0] + list(c["ratios"])
    d = [0.0] + list(c["max_abs_dT_K"])
    ax.plot([100 * x for x in r], d, marker="o", ms=3, label=f'{c["node"]} ({c.get("faces_before", "?")} faces)')
ax.axhline(data["tolerance_K"], color="k", ls="--", lw=1, label=f'tolerance {data["tolerance_K"]} K')
if "noise_floor_K" in data:
    ax.axhline(max(data["noise_floor_K"], 1e-6), color="grey", ls=":", lw=1, label="noise floor")
top = max([data["tolerance_K"] * 2] + [max(c["max_abs_dT_K"] or [0]) for c in curves])
ax.set_ylim(0, min(top, data.get("cap_K", top)) * 1.15 if top > 0 else 1)
ax.set_xlabel("reduction ratio of the node alone [% faces removed]")
ax.set_ylabel("max |dT| over all nodes and the orbit [K]")
ax.set_title("Sensitivity of each thermal node to decimation (smallest node first)")
ax.grid(True, alpha=0.3)
ax.legend(fontsize=7, ncol=2)
save(fig, out)
