"""Reference vs reduced model temperatures. Top: every node's reference temperature over the
orbit (wide pale line) with the reduced model on top (thin dashed line, same colour), labelled
at the right. Bottom: dT = reduced - reference per node with the +/- tolerance band. Grey
bands: eclipse. Input: {"times_s", "nodes", "reference_K": {node: [...]}, "reduced_K":
{node: [...]}, "tolerance_K", "period_s", "in_shadow": [...], "node_map" (a merged reduction: its
merged nodes' members are listed under the plot)}"""
from _common import load_args, plt, save
from _style import node_style, note_merged, shade_eclipse

data, out = load_args()
t = [x / 60.0 for x in data["times_s"]]
tol = data.get("tolerance_K")
nodes = data["nodes"]
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(11, 8), sharex=len(t) > 1, gridspec_kw={"height_ratios": [3, 2]})
dT = {n: [b - a for a, b in zip(data["reference_K"][n], data["reduced_K"][n])] for n in nodes}
if len(t) > 1:
    eclipse = False
    for a in (ax, ax2):
        eclipse = shade_eclipse(a, t, data.get("in_shadow"), data.get("period_s", 0.0) / 60.0) or eclipse
    for i, n in enumerate(nodes):
        st = node_style(i)
        ref, red = data["reference_K"][n], data["reduced_K"][n]
        ax.plot(t, ref, color=st["color"], lw=4, alpha=0.35, solid_capstyle="butt")
        ax.plot(t, red, color=st["color"], lw=1.1, ls="--")
        ax.annotate(n, (t[-1], ref[-1]), xytext=(4, 0), textcoords="offset points", fontsize=7, color=st["color"],
                    va="center")
        ax2.plot(t, dT[n], color=st["color"], ls=st["ls"], lw=1.2, label=n)
    ax.plot([], [], color="0.5", lw=4, alpha=0.35, label="reference")
    ax.plot([], [], color="0.3", lw=1.1, ls="--", label="reduced")
    if eclipse:
        ax.fill_between([], [], color="0.88", label="eclipse")
    ax.legend(fontsize=8, loc="upper left")
    ax2.set_xlabel("time since ascending node [min]")
else:
    x = list(range(len(nodes)))
    ax.scatter(x, [data["reference_K"][n][0] for n in nodes], s=80, c="0.7", label="reference")
    ax.scatter(x, [data["reduced_K"][n][0] for n in nodes], s=25, c="tab:blue", marker="x", label="reduced")
    ax.legend(fontsize=8)
    ax2.bar(x, [dT[n][0] for n in nodes], color=[node_style(i)["color"] for i in range(len(nodes))])
    ax2.set_xticks(x)
    ax2.set_xticklabels(nodes, rotation=45, ha="right", fontsize=7)
ax.set_ylabel("temperature [K]")
ax.set_title("Node temperatures: reference vs reduced model")
ax.grid(True, alpha=0.3)
if tol:
    ax2.axhspan(-tol, tol, color="tab:green", alpha=0.12, lw=0, label=f"±tolerance {tol:g} K")
ax2.axhline(0, color="k", lw=0.8)
ax2.set_ylabel("dT = reduced − reference [K]")
ax2.grid(True, alpha=0.3)
if len(t) > 1:
    # Legend: the band and the nodes with the largest |dT| (all nodes are labelled above).
    worst = sorted(nodes, key=lambda n: -max(abs(v) for v in dT[n]))[:8]
    handles, labels = ax2.get_legend_handles_labels()
    keep = [(h, l) for h, l in zip(handles, labels) if l in worst or l.startswith("±")]
    ax2.legend([h for h, _ in keep], [l for _, l in keep], fontsize=7, ncol=3, loc="upper left",
               title="largest |dT| nodes", title_fontsize=7)
lim = max([abs(v) for n in nodes for v in dT[n]] + [tol or 0]) * 1.3 or 1.0
ax2.set_ylim(-lim, lim)
fig.tight_layout()
note_merged(fig, data.get("node_map"), nodes)
save(fig, out)
