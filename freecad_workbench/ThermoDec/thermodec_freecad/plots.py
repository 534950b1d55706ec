"""In-GUI plots of an analysis (matplotlib in a dock): node temperatures over the orbit, the
dense model against the reduced one, and the reduction's sensitivity curves (max |dT| of each
node reduced alone against its face ratio, from reduced/report.json).

The data functions import no GUI and run headless; PlotDock is the GUI part.
"""

import json
import os

import numpy as np

from . import objects, thermal_result
from .errors import ThermoDecError


def _result_on(analysis, mesh_name):
    if mesh_name == "ThermalMesh":
        mesh = analysis.ThermalMesh
    else:
        mesh = analysis.Document.getObject(mesh_name)
    found = [r for r in objects.members(analysis, thermal_result.ThermalResult)
             if mesh is not None and r.ResultMesh == mesh]
    return found[-1] if found else None


def _node_map(model_path):
    """The node_map {original: merged} of a (reduced) model file; {} when it has none."""
    try:
        with open(model_path, encoding="utf-8") as f:
            return dict(json.load(f).get("node_map", {}))
    except (OSError, ValueError, TypeError, AttributeError):
        return {}


def orbit_series(analysis):
    """{"times_s", "nodes", "dense" #N x #S [K], "reduced" #N x #S or None, "merged_into"
    {node: merged node}, "stale"} of the analysis' dense result (on its ThermalMesh) and reduced
    result (ReducedMesh), nodes in the dense result's order. A reduced model with merged nodes
    (its node_map) gives each original node its merged node's temperatures, as `thermodec
    compare` does. Raises ThermoDecError when there is no dense result."""
    dense = _result_on(analysis, "ThermalMesh")
    if dense is None:
        raise ThermoDecError("simulate first: the analysis has no result on its ThermalMesh")
    nodes, times, T = thermal_result.matrix(dense)
    out = {"times_s": times, "nodes": nodes, "dense": T, "reduced": None, "merged_into": {},
           "stale": bool(dense.Stale), "dense_label": dense.Label}
    reduced = _result_on(analysis, "ReducedMesh")
    if reduced is not None:
        rnodes, rtimes, R = thermal_result.matrix(reduced)
        node_map = _node_map(analysis.ReducedModelFile) if analysis.ReducedModelFile else {}
        into = [node_map.get(n, n) for n in nodes]
        if len(rtimes) == len(times) and set(into) == set(rnodes):
            out["reduced"] = R[[rnodes.index(m) for m in into]]
            out["merged_into"] = {n: m for n, m in zip(nodes, into) if m != n}
            out["stale"] = out["stale"] or bool(reduced.Stale)
            out["reduced_label"] = reduced.Label
    return out


def report_path(analysis):
    """reduced/report.json of the analysis' last Reduce, or '' when there is none."""
    if not analysis.ReducedModelFile:
        return ""
    path = os.path.join(os.path.dirname(analysis.ReducedModelFile), "report.json")
    return path if os.path.exists(path) else ""


def sensitivity_curves(path):
    """(tolerance [K], [(node, ratios, max |dT| [K], chosen ratio)]) from a reduction report."""
    try:
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
        curves = [(c["node"], np.asarray(c["ratios"], float), np.asarray(c["max_abs_dT_K"], float),
                   float(c.get("chosen_ratio", float("nan")))) for c in report.get("sensitivity", [])]
        return float(report["tolerance_K"]), curves
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise ThermoDecError("cannot read the sensitivity curves of %s: %s" % (path, e)) from None


def draw_orbit(figure, series, node=None):
    """Temperature over the orbit [K] against time [min]: one node (dense solid, reduced
    dashed) or, node None, every node (dense only, reduced dashed when there)."""
    figure.clear()
    ax = figure.add_subplot(111)
    t = series["times_s"] / 60.0
    names = series["nodes"] if node is None else [node]
    for name in names:
        k = series["nodes"].index(name)
        line, = ax.plot(t, series["dense"][k], "-", lw=1.4, label="%s original" % name if node else name)
        if series["reduced"] is not None:
            merged = series.get("merged_into", {}).get(name)
            ax.plot(t, series["reduced"][k], "--", lw=1.4, color=line.get_color(),
                    label=("%s reduced" % name if not merged else "%s reduced (merged into %s)" % (name, merged))
                    if node else None)
    title = "node temperatures over the orbit" if node is None else node
    if series["reduced"] is not None:
        d = np.abs(series["reduced"] - series["dense"])
        k = None if node is None else series["nodes"].index(node)
        title += ": max |dT| reduced vs original %.3g K" % (d.max() if k is None else d[k].max())
    if series["stale"]:
        title += "\n(stale: an input changed since these results)"
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("time [min]")
    ax.set_ylabel("temperature [K]")
    ax.grid(alpha=0.3)
    if node is not None or len(names) <= 14:
        ax.legend(fontsize=7, ncol=2 if node is None else 1)
    figure.tight_layout()


def draw_sensitivity(figure, tolerance_K, curves):
    """Each node reduced alone: max |dT| [K] against the ratio of its faces removed, the
    tolerance as a line, the chosen ratio as a dot."""
    figure.clear()
    ax = figure.add_subplot(111)
    for node, ratios, dT, chosen in curves:
        line, = ax.plot(ratios, dT, ".-", lw=1.2, label=node)
        if np.isfinite(chosen) and len(ratios):
            ax.plot([chosen], [np.interp(chosen, ratios, dT)], "o", color=line.get_color())
    ax.axhline(tolerance_K, color="k", lw=0.8, ls=":", label="tolerance %.3g K" % tolerance_K)
    ax.set_xlabel("fraction of the node's faces removed")
    ax.set_ylabel("max |dT| [K]")
    ax.set_title("sensitivity of each node to reduction", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    figure.tight_layout()


# ---------------------------------------------------------------------------------------------
# GUI

DOCK_NAME = "ThermoDecPlots"
#: The dock shown (its Python side must outlive the command that made it: its slots live here).
_current = None


class PlotDock:
    """A dock at the right of FreeCAD's window with two tabs: temperatures over the orbit (a
    node chooser: every node, or one with original vs reduced) and the sensitivity curves."""

    def __init__(self, analysis):
        import FreeCADGui
        from PySide import QtCore, QtGui
        from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
        from matplotlib.figure import Figure
        self.analysis = analysis
        window = FreeCADGui.getMainWindow()
        old = window.findChild(QtGui.QDockWidget, DOCK_NAME)
        if old is not None:
            window.removeDockWidget(old)
            old.setObjectName("")
            old.deleteLater()
        self.dock = QtGui.QDockWidget("ThermoDec plots", window)
        self.dock.setObjectName(DOCK_NAME)
        tabs = QtGui.QTabWidget()
        orbit = QtGui.QWidget()
        layout = QtGui.QVBoxLayout(orbit)
        self.node = QtGui.QComboBox()
        layout.addWidget(self.node)
        self.orbit_figure = Figure(figsize=(5, 3.6), dpi=90)
        self.orbit_canvas = FigureCanvasQTAgg(self.orbit_figure)
        layout.addWidget(self.orbit_canvas)
        tabs.addTab(orbit, "Temperatures")
        self.sens_figure = Figure(figsize=(5, 3.6), dpi=90)
        self.sens_canvas = FigureCanvasQTAgg(self.sens_figure)
        tabs.addTab(self.sens_canvas, "Sensitivity")
        self.tabs = tabs
        self.dock.setWidget(tabs)
        self.dock.setMinimumWidth(480)
        window.addDockWidget(QtCore.Qt.RightDockWidgetArea, self.dock)
        self.dock.setFloating(False)
        self.dock.show()
        self.dock.raise_()
        self.node.currentIndexChanged.connect(self._draw_orbit)
        self.refresh()
        global _current
        _current = self

    def refresh(self):
        shown = self.node.currentText()
        self.series = orbit_series(self.analysis)
        self.node.blockSignals(True)
        self.node.clear()
        self.node.addItems(["all nodes"] + list(self.series["nodes"]))
        if shown in self.series["nodes"]:
            self.node.setCurrentIndex(1 + list(self.series["nodes"]).index(shown))
        self.node.blockSignals(False)
        self._draw_orbit()
        path = report_path(self.analysis)
        if path:
            draw_sensitivity(self.sens_figure, *sensitivity_curves(path))
        else:
            self.sens_figure.clear()
            self.sens_figure.text(0.5, 0.5, "Reduce first: no sensitivity curves yet", ha="center")
        self.sens_canvas.draw()

    def _draw_orbit(self, *args):
        k = self.node.currentIndex()
        draw_orbit(self.orbit_figure, self.series, None if k <= 0 else self.series["nodes"][k - 1])
        self.orbit_canvas.draw()
