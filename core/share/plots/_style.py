"""Distinct per-node styles: 16 colours x 4 line styles x markers, so no two of up to 64
nodes share a look (a repeated colour made two curves indistinguishable)."""
from _common import plt

# Saturated colours only (tab20's pale halves are hard to tell from the background).
_COLOURS = list(plt.cm.tab10.colors) + ["#000000", "#7f0000", "#006400", "#00008b", "#b8860b", "#8b008b"]
_STYLES = ["-", "--", "-.", ":"]
_MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]


def node_style(i):
    colour = _COLOURS[i % len(_COLOURS)]
    return {"color": colour, "ls": _STYLES[(i // len(_COLOURS)) % 4], "marker": _MARKERS[i % len(_MARKERS)]}


def shade_eclipse(ax, times_min, in_shadow, period_min):
    """Grey bands where the spacecraft is in Earth's shadow."""
    if not in_shadow or len(times_min) < 2:
        return False
    dt = period_min / len(times_min) if period_min else times_min[1] - times_min[0]
    shaded = False
    for t, dark in zip(times_min, in_shadow):
        if dark:
            ax.axvspan(t - dt / 2, t + dt / 2, color="0.88", lw=0, zorder=0)
            shaded = True
    return shaded
