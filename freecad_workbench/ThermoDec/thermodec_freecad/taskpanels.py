"""Task panels (GUI only). Each panel edits plain values and writes them back on accept only,
through gui_actions.run (one undoable transaction, replayable script lines)."""

import FreeCADGui
from PySide import QtCore, QtGui

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


def _colour_bar(low, high, height=220):
    """The colour map as a picture for the panel: bands bottom (low) to top (high) [K]."""
    from .temperature_field import legend
    bands, _ = legend(low, high)
    pixmap = QtGui.QPixmap(28, height)
    painter = QtGui.QPainter(pixmap)
    step = height / float(len(bands))
    for k, (_, (r, g, b)) in enumerate(bands):
        top = int(round(height - (k + 1) * step))
        painter.fillRect(0, top, 28, int(round(height - k * step)) - top,
                         QtGui.QColor(int(255 * r), int(255 * g), int(255 * b)))
    painter.end()
    return pixmap


class ResultPanel(_Panel):
    """A ThermalResult: per-node min / mean / max over the orbit (a table), the colour bar of
    the field shown, and the choice of that field (a statistic or one time step). Choices
    preview at once; OK keeps them as one undoable transaction, Cancel restores."""

    def __init__(self, result):
        from . import temperature_field, thermal_result
        self.result = result
        self.original = thermal_result.field(result)
        nodes, self.times, T = thermal_result.matrix(result)
        self.rows = temperature_field.statistics_table(nodes, T)
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Thermal result")
        layout = QtGui.QVBoxLayout(self.form)
        run = "%d time steps, %.1f s apart" % (len(self.times), self.times[1] - self.times[0]) \
            if len(self.times) > 1 else "steady state"
        used = ("seed %d, %d rays per face" % (result.Seed, result.RaysPerFace)) if result.Seed >= 0 \
            else "seed and rays not recorded (imported result)"
        info = QtGui.QLabel("%s on %s\n%s; %s" % (result.Label, result.ResultMesh.Label, run, used))
        info.setWordWrap(True)
        layout.addWidget(info)

        form = QtGui.QFormLayout()
        self.field = QtGui.QComboBox()
        self.field.addItems(["mean over the orbit", "min over the orbit", "max over the orbit", "time step"])
        self.step = QtGui.QSlider()
        self.step.setOrientation(QtCore.Qt.Horizontal)
        self.step.setRange(0, max(len(self.times) - 1, 0))
        self.step_label = QtGui.QLabel()
        form.addRow("Show", self.field)
        form.addRow("Time step", self.step)
        form.addRow("", self.step_label)
        layout.addLayout(form)

        bar = QtGui.QHBoxLayout()
        self.bar = QtGui.QLabel()
        ticks = QtGui.QVBoxLayout()
        self.top, self.bottom = QtGui.QLabel(), QtGui.QLabel()
        self.shown = QtGui.QLabel()
        self.shown.setWordWrap(True)
        ticks.addWidget(self.top)
        ticks.addStretch(1)
        ticks.addWidget(self.shown)
        ticks.addStretch(1)
        ticks.addWidget(self.bottom)
        bar.addWidget(self.bar)
        bar.addLayout(ticks, 1)
        layout.addLayout(bar)

        self.table = QtGui.QTableWidget(len(self.rows), 5)
        self.table.setHorizontalHeaderLabels(["node", "min [K]", "mean [K]", "max [K]", "shown [K]"])
        for i, row in enumerate(self.rows):
            self.table.setItem(i, 0, QtGui.QTableWidgetItem(row[0]))
            for j, value in enumerate(row[1:]):
                item = QtGui.QTableWidgetItem("%.2f" % value)
                item.setTextAlignment(0x0082)  # right, vertically centred
                self.table.setItem(i, j + 1, item)
        self.table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self._fill_shown()
        self.table.resizeColumnsToContents()
        self.form.setMinimumWidth(sum(self.table.columnWidth(j) for j in range(5)) + 24)
        self.table.verticalHeader().setVisible(False)
        self.table.verticalHeader().setDefaultSectionSize(self.table.fontMetrics().height() + 6)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.setMinimumHeight(min(30 + 24 * len(self.rows), 420))
        layout.addWidget(self.table)

        self._set_controls(self.original)
        self.field.currentIndexChanged.connect(self._changed)
        self.step.valueChanged.connect(self._changed)
        self._show_bar()

    def _set_controls(self, field):
        index = {"mean": 0, "min": 1, "max": 2}
        self.field.setCurrentIndex(index.get(field, 3))
        if field not in index:
            self.step.setValue(int(field))
        self._label_step()

    def _label_step(self):
        k = self.step.value()
        self.step.setEnabled(self.field.currentIndex() == 3)
        if len(self.times):
            self.step_label.setText("step %d of %d, t = %.0f s" % (k, len(self.times) - 1, self.times[k]))

    def choice(self):
        """The field the controls select: 'mean' / 'min' / 'max' or a time step index."""
        k = self.field.currentIndex()
        return ("mean", "min", "max")[k] if k < 3 else self.step.value()

    def _show_bar(self):
        r = self.result
        self.bar.setPixmap(_colour_bar(r.ColourMinK, r.ColourMaxK))
        self.top.setText("%.1f K (red)" % r.ColourMaxK)
        self.bottom.setText("%.1f K (blue)" % r.ColourMinK)
        self.shown.setText("colour: node temperature,\n%s" % r.Shown)

    def _fill_shown(self):
        """The table's last column: each node's value in the field shown."""
        from . import temperature_field, thermal_result
        nodes, _, T = thermal_result.matrix(self.result)
        values = dict(zip(nodes, temperature_field.node_field(T, self.choice())))
        for i, row in enumerate(self.rows):
            item = QtGui.QTableWidgetItem("%.2f" % values[row[0]])
            item.setTextAlignment(0x0082)
            self.table.setItem(i, 4, item)

    def _changed(self, *args):
        from . import thermal_result
        self._label_step()
        thermal_result.set_field(self.result, self.choice())  # preview; OK records it
        self._fill_shown()
        self._show_bar()
        FreeCADGui.updateGui()

    def accept(self):
        from . import thermal_result
        choice = self.choice()
        thermal_result.set_field(self.result, self.original)  # so that undo returns here
        ok = gui_actions.run("Show thermal result", [
            "import thermodec_freecad.thermal_result as tdresult",
            "tdresult.set_field(App.ActiveDocument.%s, %r)" % (self.result.Name, choice)])
        if ok:
            self._close()
        return ok

    def reject(self):
        from . import thermal_result
        thermal_result.set_field(self.result, self.original)
        self._close()
        return True

    def _close(self):
        doc = FreeCADGui.ActiveDocument
        if doc is not None and doc.getInEdit() is not None:
            doc.resetEdit()  # opened by double-click: unsetEdit closes the panel
        else:
            FreeCADGui.Control.closeDialog()

