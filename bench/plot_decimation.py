#!/usr/bin/python3
"""Figure for docs/decimation.md from bench_decimation's CSV files.

usage: plot_decimation.py OUT.png LABEL=bench.csv [LABEL=bench.csv ...]
One row of panels per CSV: max node-area error, max closed-volume error, CPU time vs ratio.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "thermodec": ("thermodec (node-preserving LT)", "tab:blue", "o"),
    "meshlab_default": ("MeshLab QEC, defaults", "tab:red", "s"),
    "meshlab_preserving": ("MeshLab QEC, boundary+normal+topology+planar", "tab:orange", "^"),
}


def read(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            rows.setdefault(r["method"], []).append(r)
    return rows


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, sets = sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]]
    fig, axes = plt.subplots(len(sets), 3, figsize=(14, 3.8 * len(sets)), squeeze=False)
    floor = 1e-6  # % ; zero errors are drawn on the floor of the log axis
    for row, (label, path) in enumerate(sets):
        data = read(path)
        for method, rs in data.items():
            name, color, marker = STYLE.get(method, (method, None, "x"))
            x = [100 * float(r["ratio"]) for r in rs]
            area = [max(100 * float(r["max_node_area_error"]), floor) for r in rs]
            vol = [max(100 * float(r["max_closed_volume_error"]), floor) for r in rs]
            t = [1e3 * float(r["seconds"]) for r in rs]
            axes[row][0].semilogy(x, area, marker=marker, color=color, label=name)
            axes[row][1].semilogy(x, vol, marker=marker, color=color, label=name)
            axes[row][2].plot(x, t, marker=marker, color=color, label=name)
        axes[row][0].axhline(0.5, color="gray", ls="--", lw=0.8)
        axes[row][0].set_ylabel(f"{label}\nmax node area error [%]")
        axes[row][1].axhline(1.0, color="gray", ls="--", lw=0.8)
        axes[row][1].set_ylabel("max closed-part volume error [%]")
        axes[row][2].set_ylabel("CPU time [ms]")
        for ax in axes[row]:
            ax.set_xlabel("faces removed [%]")
            ax.grid(True, which="both", alpha=0.3)
    axes[0][2].legend(fontsize=8)
    fig.tight_layout()
    tmp = os.path.join(os.path.dirname(os.path.abspath(out)), "." + os.path.basename(out) + ".tmp.png")
    fig.savefig(tmp, dpi=100, bbox_inches="tight")
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
