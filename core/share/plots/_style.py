"""Distinct per-node styles: 20 colours x 4 line styles x markers, so no two of up to 80
nodes share a look (a repeated colour made two curves indistinguishable)."""
from _common import plt

_COLOURS = plt.cm.tab20.colors
_STYLES = ["-", "--", "-.", ":"]
_MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]


def node_style(i):
    colour = _COLOURS[(2 * i) % 20 if i < 10 else (2 * (i - 10) + 1) % 20]
    return {"color": colour, "ls": _STYLES[(i // 20) % 4], "marker": _MARKERS[i % len(_MARKERS)]}


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
