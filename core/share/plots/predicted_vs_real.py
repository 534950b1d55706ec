"""Predicted vs real temperature difference (paper Fig. 11 analogue). Input: {"points":
[{"target_K": t, "predicted_K": p, "real_K": r, "label": s}], "tolerance_K": t}"""
from _common import load_args, plt, save

data, out = load_args()
fig, ax = plt.subplots(figsize=(5.5, 5))
pts = data["points"]
xs = [p["predicted_K"] for p in pts]
ys = [p["real_K"] for p in pts]
ax.scatter(xs, ys, c="tab:blue", s=25, zorder=3)
for p in pts:
    if p.get("label"):
        ax.annotate(p["label"], (p["predicted_K"], p["real_K"]), fontsize=6, xytext=(3, 3), textcoords="offset points")
hi = max(xs + ys + [data.get("tolerance_K", 0.0)]) * 1.1 or 1.0
ax.plot([0, hi], [0, hi], "k--", lw=1, label="y = x")
if "tolerance_K" in data:
    ax.axhline(data["tolerance_K"], color="tab:red", lw=1, ls=":", label="tolerance")
ax.set_xlim(0, hi)
ax.set_ylim(0, hi)
ax.set_xlabel("target max |dT| the curves predicted for [K]")
ax.set_ylabel("real (simulated) max |dT| [K]")
ax.set_title("Prediction vs simulation")
ax.grid(True, alpha=0.3)
ax.legend(fontsize=8)
save(fig, out)
