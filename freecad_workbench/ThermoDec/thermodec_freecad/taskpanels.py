"""Task panels (GUI only). Each panel edits plain values and writes them back on accept only,
through gui_actions.run (one undoable transaction, replayable script lines)."""

import FreeCADGui
from PySide import QtGui

from . import coatings, gui_actions, objects


def _form(title):
    widget = QtGui.QWidget()
    widget.setWindowTitle(title)
    layout = QtGui.QFormLayout(widget)
    return widget, layout


def _spin(value, low, high, decimals, suffix):
    box = QtGui.QDoubleSpinBox()
    box.setRange(low, high)
    box.setDecimals(decimals)
    box.setValue(value)
    box.setSuffix(" " + suffix)
    return box


class _Panel:
    def reject(self):
        FreeCADGui.Control.closeDialog()
        return True

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)


class NodePanel(_Panel):
    def __init__(self, analysis, refs):
        self.analysis, self.refs = analysis, refs
        self.form, layout = _form("Thermal node")
        self.name = QtGui.QLineEdit("Node")
        self.materials = [m for m in objects.members(analysis, objects.ThermalMaterial)]
        self.material = QtGui.QComboBox()
        self.material.addItems(["(analysis default)"] + [m.Label for m in self.materials])
        self.capacitance = _spin(0.0, 0.0, 1e9, 2, "J/K")
        self.power = _spin(0.0, -1e6, 1e6, 3, "W")
        self.boundary = QtGui.QCheckBox("held at fixed temperature")
        self.temperature = _spin(293.15, 0.0, 5000.0, 2, "K")
        count = sum(len([s for s in subs if s]) or 1 for _, subs in refs)
        layout.addRow(QtGui.QLabel("%d face/shape reference(s) selected" % count))
        for label, w in (("Name", self.name), ("Material", self.material), ("Capacitance", self.capacitance),
                         ("Power", self.power), ("", self.boundary), ("Temperature", self.temperature)):
            layout.addRow(label, w)

    def accept(self):
        k = self.material.currentIndex()
        material = "App.ActiveDocument.%s" % self.materials[k - 1].Name if k > 0 else "None"
        fixed = repr(self.temperature.value()) if self.boundary.isChecked() else "None"
        ok = gui_actions.run("Thermal node", [
            "analysis = App.ActiveDocument.%s" % self.analysis.Name,
            "node = tdo.makeNode(analysis, %s, name=%r, material=%s, capacitance=%r, power=%r, "
            "fixed_temperature=%s)" % (gui_actions.refs_code(self.refs), self.name.text() or "Node", material,
                                       self.capacitance.value(), self.power.value(), fixed),
            "node.Label = %r" % (self.name.text() or "Node")])
        if ok:
            FreeCADGui.Control.closeDialog()
        return ok


class MaterialPanel(_Panel):
    def __init__(self, analysis, refs, nodes):
        self.analysis, self.refs, self.nodes = analysis, refs, nodes
        self.form, layout = _form("Thermal material")
        self.existing = objects.members(analysis, objects.ThermalMaterial)
        self.choice = QtGui.QComboBox()
        self.choice.addItems(["library: " + n for n in coatings.coating_names()] +
                             ["existing: " + m.Label for m in self.existing])
        self.info = QtGui.QLabel()
        self.info.setWordWrap(True)
        self.choice.currentIndexChanged.connect(self._show)
        target = "%d node(s)" % len(nodes) if nodes else "%d face/shape reference(s)" % len(refs)
        layout.addRow(QtGui.QLabel("Applies to " + target))
        layout.addRow("Coating", self.choice)
        layout.addRow(self.info)
        self._show(0)

    def _show(self, k):
        names = coatings.coating_names()
        if k < len(names):
            a, e, source = coatings.coating(names[k])
        else:
            m = self.existing[k - len(names)]
            a, e, source = m.Absorptivity, m.Emissivity, m.Source
        self.info.setText("absorptivity %.3g, emissivity %.3g\n%s" % (a, e, source))

    def accept(self):
        k = self.choice.currentIndex()
        names = coatings.coating_names()
        lines = ["analysis = App.ActiveDocument.%s" % self.analysis.Name]
        reuse = [m for m in self.existing if m.Coating == names[k]] if k < len(names) else []
        if reuse:  # one material object per library coating
            lines.append("mat = App.ActiveDocument.%s" % reuse[0].Name)
        elif k < len(names):
            lines.append("mat = tdo.makeMaterial(analysis, %r)" % names[k])
        else:
            lines.append("mat = App.ActiveDocument.%s" % self.existing[k - len(names)].Name)
        for node in self.nodes:
            lines.append("App.ActiveDocument.%s.Material = mat" % node.Name)
        if self.refs and not self.nodes:
            lines.append("tdo.assign_material(mat, %s)" % gui_actions.refs_code(self.refs))
        ok = gui_actions.run("Thermal material", lines)
        if ok:
            FreeCADGui.Control.closeDialog()
        return ok


class TessellatePanel(_Panel):
    def __init__(self, analysis):
        self.analysis = analysis
        self.form, layout = _form("Tessellate")
        self.length = _spin(float(analysis.MaxEdgeLength.getValueAs("mm")), 0.01, 1e6, 2, "mm")
        layout.addRow("Max edge length", self.length)
        layout.addRow(QtGui.QLabel("Each B-rep face is meshed on its own (Mefisto) and welded;\n"
                                   "triangles keep their node and material."))

    def accept(self):
        gui_actions.status("ThermoDec: tessellating ...")
        ok = gui_actions.run("Tessellate", [
            "analysis = App.ActiveDocument.%s" % self.analysis.Name,
            "analysis.MaxEdgeLength = '%r mm'" % self.length.value(),
            "import thermodec_freecad.tessellate as tdtess",
            "tdtess.tessellate(analysis)"])
        if ok:
            tm = self.analysis.ThermalMesh
            gui_actions.status("ThermoDec: %d triangles, longest edge %.1f mm" % (tm.Mesh.CountFacets, tm.LongestEdge))
            FreeCADGui.Control.closeDialog()
        return ok
