"""A picture of a mesh coloured per face (by node or by a value such as dT). Input:
{"title": s, "vertices": [[x,y,z]...], "faces": [[i,j,k]...], "face_value": [...],
"categorical": bool, "value_label": s, "labels": [...]} ; optional "panels": list of such
dicts drawn side by side."""
import matplotlib.cm as cm
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from _common import load_args, plt, save

data, out = load_args()
panels = data.get("panels", [data])
fig = plt.figure(figsize=(5 * len(panels), 5))
for i, p in enumerate(panels):
    ax = fig.add_subplot(1, len(panels), i + 1, projection="3d")
    V, F, val = p["vertices"], p["faces"], p["face_value"]
    tris = [[V[a], V[b], V[c]] for a, b, c in F]
    if p.get("categorical", True):
        cmap = plt.get_cmap("tab20")
        colors = [cmap(int(v) % 20) for v in val]
    else:
        lo, hi = min(val), max(val)
        norm = plt.Normalize(lo, hi if hi > lo else lo + 1e-9)
        cmap = plt.get_cmap("inferno")
        colors = [cmap(norm(v)) for v in val]
        sm = cm.ScalarMappable(norm=norm, cmap=cmap)
        fig.colorbar(sm, ax=ax, shrink=0.6, label=p.get("value_label", ""))
    ax.add_collection3d(Poly3DCollection(tris, facecolors=colors, edgecolors=(0, 0, 0, 0.35), linewidths=0.2))
    xs, ys, zs = zip(*V)
    c = [(max(a) + min(a)) / 2 for a in (xs, ys, zs)]
    r = max(max(a) - min(a) for a in (xs, ys, zs)) / 2 * 0.75
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.view_init(elev=25, azim=-60)
    try:
        ax.set_box_aspect((1, 1, 1), zoom=1.9)
    except TypeError:  # matplotlib < 3.6
        ax.set_box_aspect((1, 1, 1))
    ax.set_title(p.get("title", ""), fontsize=10)
    ax.set_axis_off()
fig.subplots_adjust(wspace=0.0, left=0, right=1)
save(fig, out)
