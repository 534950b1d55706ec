"""Per-node sensitivity curves (paper Fig. 10): max |dT| of the whole model vs the node's
reduction ratio, with the ratio chosen for each node marked (star) and the tolerance
labelled. Input: {"tolerance_K": t, "noise_floor_K": n, "curves": [{"node": name,
"faces_before": n, "ratios": [...], "max_abs_dT_K": [...], "chosen_ratio": r}]}"""
import numpy as np

from _common import load_args, plt, save
from _style import node_style

data, out = load_args()
tol = data["tolerance_K"]
fig, ax = plt.subplots(figsize=(10, 6))
curves = sorted(data["curves"], key=lambda c: c.get("faces_before", 0))
top = max([tol * 2] + [max(c["max_abs_dT_K"] or [0]) for c in curves])
# The axis spans three tolerances so the region that decides the ratios stays readable;
# values above it are drawn at the top edge with their value.
ymax = min(top, 3 * tol) * 1.1 if top > 0 else 1
for i, c in enumerate(curves):
    st = node_style(i)
    r = [0.0] + list(c["ratios"])
    d = [0.0] + list(c["max_abs_dT_K"])
    crosses = max(d) > tol
    ax.plot([100 * x for x in r], [min(v, ymax) for v in d], color=st["color"], ls=st["ls"], marker=st["marker"],
            ms=4, lw=2.6 if crosses else 1.2, label=f'{c["node"]} ({c.get("faces_before", "?")} faces)')
    for x, v in zip(r, d):
        if v > ymax:
            ax.annotate(f"{v:.2g} K", (100 * x, ymax), xytext=(0, -12), textcoords="offset points", fontsize=7,
                        color=st["color"], ha="center")
    if "chosen_ratio" in c:
        x = c["chosen_ratio"]
        y = float(np.interp(x, r, d)) if len(r) > 1 else 0.0
        ax.plot([100 * x], [min(y, ymax)], marker="*", ms=13, color=st["color"], mec="k", mew=0.7, ls="none",
                zorder=5)
    # Direct label on the curves that matter: those reaching half the tolerance.
    if max(d) > 0.5 * tol:
        k = next(j for j in range(len(d)) if d[j] > 0.5 * tol)
        ax.annotate(c["node"], (100 * r[k], min(d[k], 0.9 * ymax)), xytext=(-8, 0), textcoords="offset points",
                    fontsize=9, fontweight="bold", color=st["color"], ha="right", va="center")
ax.axhline(tol, color="tab:red", ls="--", lw=1.2)
ax.text(0.01, tol, f"tolerance {tol:g} K", color="tab:red", va="bottom", ha="left", fontsize=9,
        transform=ax.get_yaxis_transform())
if data.get("noise_floor_K"):
    nf = max(data["noise_floor_K"], 1e-6)
    ax.axhline(nf, color="grey", ls=":", lw=1)
    ax.text(0.01, nf, f"noise floor {nf:.2g} K", color="grey", va="bottom", ha="left", fontsize=8,
            transform=ax.get_yaxis_transform())
ax.plot([], [], marker="*", ms=12, color="w", mec="k", ls="none", label="ratio chosen for the node")
ax.set_ylim(0, ymax)
ax.set_xlim(0, 100)
ax.set_xlabel("reduction ratio of the node alone [% faces removed]")
ax.set_ylabel("max |dT| over all nodes and the orbit [K]")
ax.set_title("Sensitivity of each thermal node to decimation (star: chosen ratio)")
ax.grid(True, alpha=0.3)
ax.legend(fontsize=7, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
save(fig, out)
