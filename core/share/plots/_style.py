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


def merged_members(node_map, nodes=None):
    """{merged node: [original, ...]} of a node_map {original: merged} (thermodec merge,
    reduce --merge-nodes) for merged nodes of two or more members, in `nodes` order if given."""
    groups = {}
    for original, merged in (node_map or {}).items():
        groups.setdefault(merged, []).append(original)
    order = list(nodes) if nodes else sorted(groups)
    # The member a merged node is named after ("a+2": a and 2 others) first.
    return {m: sorted(groups[m], key=lambda o: not m.startswith(o + "+")) for m in order if len(groups.get(m, [])) > 1}


def member_list(members, max_shown=6, sep=" + "):
    """The members joined by `sep`; a longer list than max_shown keeps its first max_shown - 1
    and counts the rest ("a + b + c + d + e … (+15 more)": the node_map has them all)."""
    members = list(members)
    if len(members) <= max_shown:
        return sep.join(members)
    return "%s \u2026 (+%d more)" % (sep.join(members[:max_shown - 1]), len(members) - max_shown + 1)


def note_merged(fig, node_map, nodes=None, max_rows=12):
    """A footnote listing each merged node's members ("a+2 = a + b + c", long lists cut by
    member_list); returns its rows."""
    groups = merged_members(node_map, nodes)
    if not groups:
        return 0
    rows = ["%s = %s" % (m, member_list(members)) for m, members in groups.items()]
    if len(rows) > max_rows:
        rows = rows[:max_rows - 1] + ["... and %d more merged nodes (node_map)" % (len(rows) - max_rows + 1)]
    fig.text(0.01, 0.0, "merged nodes (isothermal): " + ";  ".join(rows), fontsize=7, ha="left", va="top",
             wrap=True, transform=fig.transFigure)
    return len(rows)
