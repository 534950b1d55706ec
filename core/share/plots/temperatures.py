"""Temperature of every node over the orbit (thermodec simulate --plot).

Input: the result JSON of `thermodec simulate` (nodes, times_s, temperatures_K, in_shadow, and
node_map for a merged model: its merged nodes' members are listed under the plot).
"""
from _common import load_args, plt, save
from _style import note_merged

data, out = load_args()
times = [t / 60.0 for t in data["times_s"]]
fig, ax = plt.subplots(figsize=(10, 5.5))
if len(times) > 1:
    shadow = data.get("in_shadow") or []
    period = data.get("period_s", 0.0) / 60.0
    dt = period / len(times) if period else 0.0
    for t, dark in zip(times, shadow):
        if dark:
            ax.axvspan(t - dt / 2, t + dt / 2, color="0.88", lw=0)
    colours = plt.cm.tab20.colors
    styles = ["-", "--", ":", "-."]
    for i, node in enumerate(data["nodes"]):
        ax.plot(times, data["temperatures_K"][node], label=node, lw=1.4,
                color=colours[(2 * i) % 20 if i < 10 else (2 * i + 1) % 20], ls=styles[(i // 10) % 4])
    ax.set_xlabel("time since ascending node [min]  (grey: eclipse)")
    ax.set_title("Orbit-periodic temperatures")
else:
    nodes = data["nodes"]
    values = [data["temperatures_K"][n][0] for n in nodes]
    ax.barh(nodes, values)
    ax.set_xlim(min(values) - 10, max(values) + 10)
    ax.set_title("Steady-state temperatures")
ax.set_ylabel("temperature [K]") if len(times) > 1 else ax.set_xlabel("temperature [K]")
ax.grid(alpha=0.3)
if len(times) > 1:
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8)
note_merged(fig, data.get("node_map"), data["nodes"])
save(fig, out)
