"""Per-node temperatures over the orbit, reference (solid) vs reduced (dashed). Input:
{"times_s": [...], "nodes": [...], "reference_K": {node: [...]}, "reduced_K": {node: [...]}}"""
from _common import load_args, plt, save

data, out = load_args()
t = [x / 60.0 for x in data["times_s"]]
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
cmap = plt.get_cmap("tab20")
for i, n in enumerate(data["nodes"]):
    ref, red = data["reference_K"][n], data["reduced_K"][n]
    c = cmap(i % 20)
    if len(t) == 1:
        ax.scatter([i], ref, color=c, label=n)
        ax.scatter([i], red, color=c, marker="x")
        ax2.scatter([i], [b - a for a, b in zip(ref, red)], color=c)
    else:
        ax.plot(t, ref, color=c, lw=1.2, label=n)
        ax.plot(t, red, color=c, lw=1.0, ls="--")
        ax2.plot(t, [b - a for a, b in zip(ref, red)], color=c, lw=1)
ax.set_ylabel("temperature [K]")
ax.set_title("Node temperatures: reference (solid) vs reduced model (dashed)")
ax.legend(fontsize=6, ncol=3)
ax.grid(True, alpha=0.3)
ax2.set_ylabel("dT [K]")
ax2.set_xlabel("time [min]" if len(t) > 1 else "node")
ax2.grid(True, alpha=0.3)
save(fig, out)
