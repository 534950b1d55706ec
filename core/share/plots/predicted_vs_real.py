"""Prediction vs verification (paper Fig. 11 analogue). Left: the max |dT| the sensitivity
curves predicted (x) against the simulated one (y). Right: the search that followed (back-off
and push trials, rejected ones marked) ending at the verified final model. Input: {"points":
[{"target_K", "predicted_K", "real_K", "label"}], "tolerance_K": t, "history": [{"action",
"max_abs_dT_K", "within_tolerance", "faces_after", "superposition_predicted_K" (optional)}],
"final": {"real_K", "faces_after"}}. The left panel also shows, for every candidate the search
measured, the superposition's prediction against the measurement, where the curves carry fields."""
from _common import load_args, plt, save

data, out = load_args()
tol = data.get("tolerance_K", 0.0)
hist = data.get("history") or []
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1, 1.5]})
pts = data["points"]
xs = [p["predicted_K"] for p in pts]
ys = [p["real_K"] for p in pts]
sup = [(h["superposition_predicted_K"], h["max_abs_dT_K"]) for h in hist if "superposition_predicted_K" in h]
hi = max(xs + ys + [v for pair in sup for v in pair] + [tol]) * 1.15 or 1.0
ax.fill_between([0, hi], 0, tol, color="tab:green", alpha=0.08, lw=0)
ax.plot([0, hi], [0, hi], "k--", lw=1, label="real = predicted")
ax.axhline(tol, color="tab:red", lw=1.2, ls="--", label=f"tolerance {tol:g} K")
ax.scatter(xs, ys, c="tab:blue", s=40, zorder=3, label="per-node curves' prediction, simulated")
if sup:
    ax.scatter([x for x, _ in sup], [y for _, y in sup], c="tab:orange", marker="D", s=22, zorder=3,
               label="superposition, each candidate the search measured")
for i, p in enumerate(pts):
    if p.get("label"):
        ax.annotate(p["label"], (p["predicted_K"], p["real_K"]), fontsize=8, xytext=(6, 6 + 10 * (i % 3)),
                    textcoords="offset points")
final = data.get("final")
if final:
    ax.scatter([max(xs) if xs else 0], [final["real_K"]], marker="*", s=220, c="tab:green", ec="k", zorder=4,
               label=f'verified final model ({final["faces_after"]} faces)')
ax.set_xlim(0, hi)
ax.set_ylim(0, hi)
ax.set_xlabel("predicted max |dT| [K]")
ax.set_ylabel("simulated max |dT| [K]")
ax.set_title("Prediction vs simulation")
ax.grid(True, alpha=0.3)
ax.legend(fontsize=8, loc="lower right")

if hist:
    steps = list(range(len(hist)))
    dts = [h["max_abs_dT_K"] for h in hist]
    ax2.plot(steps, dts, color="0.6", lw=1, zorder=1)
    ok = [i for i, h in enumerate(hist) if h["within_tolerance"]]
    bad = [i for i, h in enumerate(hist) if not h["within_tolerance"]]
    ax2.scatter(ok, [dts[i] for i in ok], c="tab:green", s=40, zorder=3, label="within tolerance")
    ax2.scatter(bad, [dts[i] for i in bad], c="tab:red", marker="x", s=50, zorder=3, label="over tolerance (rejected / backed off)")
    if final:
        ax2.scatter([len(hist) - 1 + 0.5], [final["real_K"]], marker="*", s=220, c="tab:green", ec="k", zorder=4,
                    label="verified final model")
    ax2.axhline(tol, color="tab:red", lw=1.2, ls="--")
    ax2.text(0.01, tol, f" tolerance {tol:g} K", color="tab:red", va="bottom", fontsize=8,
             transform=ax2.get_yaxis_transform())
    # The faces of each trial, and the action of the trials that changed course.
    for i, h in enumerate(hist):
        if i == 0 or "back off" in h["action"] or not h["within_tolerance"]:
            text = h["action"].split(" (")[0]
            ax2.annotate(text, (i, dts[i]), fontsize=7, xytext=(0, 9 if i % 2 == 0 else -14),
                         textcoords="offset points", color="0.25", ha="left" if i == 0 else "center")
    ax2.set_ylim(0, max(dts + [tol, final["real_K"] if final else 0]) * 1.35)
    ax2.set_xlabel("trial after the prediction (0 = prediction)")
    ax2.set_ylabel("simulated max |dT| [K]")
    ax2.legend(fontsize=8, loc="upper right")
else:
    ax2.text(0.5, 0.5, "no search after the prediction", ha="center", va="center", transform=ax2.transAxes)
ax2.set_title("Back-off and push to the verified model")
ax2.grid(True, alpha=0.3)
fig.tight_layout()
save(fig, out)
