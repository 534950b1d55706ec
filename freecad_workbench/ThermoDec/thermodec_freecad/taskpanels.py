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


#: The last panel of each class opened (scripted GUI runs reach a panel FreeCAD shows by its class name).
ACTIVE = {}


class _Panel:
    def reject(self):
        FreeCADGui.Control.closeDialog()
        return True

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)


def _area_m2(refs):
    """Total area [m^2] of face references [(object, [sub names or ''])]."""
    from . import units
    total = 0.0
    for obj, subs in refs:
        faces = [obj.Shape.getElement(s) for s in subs if s] or obj.Shape.Faces
        total += sum(units.area_m2(f.Area) for f in faces)
    return total


class NodePanel(_Panel):
    def __init__(self, analysis, refs):
        self.analysis, self.refs = analysis, refs
        self.form, layout = _form("Thermal node")
        self.name = QtGui.QLineEdit("Node")
        self.materials = [m for m in objects.members(analysis, objects.ThermalMaterial)]
        self.material = QtGui.QComboBox()
        self.material.addItems(["(analysis default)"] + [m.Label for m in self.materials])
        area = _area_m2(refs)  # the default panel's heat capacity for that area (defaults.py)
        self.capacitance = _spin(area * analysis.PanelArealHeatCapacity, 0.0, 1e9, 2, "J/K")
        self.capacitance.setToolTip("default: %.4g m^2 x %.4g J/(m^2 K) (the analysis' PanelArealHeatCapacity)"
                                    % (area, analysis.PanelArealHeatCapacity))
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
        note = QtGui.QLabel("Each B-rep face is meshed on its own (Mefisto) and welded; triangles keep "
                            "their node and material. Runs in the background (FreeCAD's console program): "
                            "progress and Cancel in the next panel.")
        note.setWordWrap(True)
        layout.addRow(note)

    def accept(self):
        """Stores the edge length (one transaction) and meshes in the background (RunPanel)."""
        if not gui_actions.run("Tessellate settings", [
                "analysis = App.ActiveDocument.%s" % self.analysis.Name,
                "analysis.MaxEdgeLength = '%r mm'" % self.length.value()]):
            return False
        FreeCADGui.Control.closeDialog()
        start_tessellate(self.analysis)
        return True


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
        ACTIVE[type(self).__name__] = self
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
        stale = ("\nSTALE: %s since; simulate (or reduce) again" % result.StaleReason) if result.Stale else ""
        info = QtGui.QLabel("%s on %s\n%s; %s%s" % (result.Label, result.ResultMesh.Label, run, used, stale))
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



# ---------------------------------------------------------------------------------------------
# Environment and Reduce: values with units (Gui::QuantitySpinBox); the properties keep
# FreeCAD quantities or SI floats, and units.py converts them for the model file.

def _quantity(text, minimum=None, maximum=None):
    """A Gui::QuantitySpinBox showing `text` (e.g. '500 km', '1361 W/m^2', '0.5 K')."""
    import FreeCAD
    box = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
    if minimum is not None:
        box.setProperty("minimum", minimum)
    if maximum is not None:
        box.setProperty("maximum", maximum)
    box.setProperty("value", FreeCAD.Units.Quantity(text))
    return box


def quantity_value(box, unit):
    """The value of a QuantitySpinBox in `unit` (a float)."""
    import FreeCAD
    return float(FreeCAD.Units.Quantity(box.property("value")).getValueAs(unit))


def _combo(items, current):
    box = QtGui.QComboBox()
    box.addItems(list(items))
    if current in items:
        box.setCurrentIndex(list(items).index(current))
    return box


class EnvironmentPanel(_Panel):
    """Orbit (altitude, inclination, RAAN, day of year, attitude, albedo, Earth IR) or fixed sun
    (direction, flux), and the analysis type (steady / transient over the orbit)."""

    def __init__(self, analysis, environment=None):
        ACTIVE[type(self).__name__] = self
        self.analysis, self.env = analysis, environment
        e = environment
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Thermal environment")
        layout = QtGui.QVBoxLayout(self.form)
        top = QtGui.QFormLayout()
        self.kind = _combo(["orbit", "fixed_sun"], e.EnvironmentType if e else "orbit")
        top.addRow("Environment", self.kind)
        layout.addLayout(top)

        self.orbit_box = QtGui.QGroupBox("Circular orbit")
        orbit = QtGui.QFormLayout(self.orbit_box)
        self.altitude = _quantity(e.Altitude.UserString if e else "500 km", 0.0)
        self.inclination = _quantity("%r deg" % (float(e.Inclination) if e else 51.6), -180.0, 180.0)
        self.raan = _quantity("%r deg" % (float(e.RAAN) if e else 0.0), -360.0, 360.0)
        self.day = QtGui.QSpinBox()
        self.day.setRange(1, 366)
        self.day.setValue(e.DayOfYear if e else 80)
        self.attitude = _combo(["nadir", "sun", "inertial"], e.Attitude if e else "nadir")
        self.albedo = _spin(e.Albedo if e else 0.30, 0.0, 1.0, 3, "")
        self.earth_ir = _quantity("%r W/m^2" % (e.EarthIRFlux if e else 237.0), 0.0)
        for label, w in (("Altitude", self.altitude), ("Inclination", self.inclination), ("RAAN", self.raan),
                         ("Day of year (sun position)", self.day), ("Attitude", self.attitude),
                         ("Albedo", self.albedo), ("Earth IR flux", self.earth_ir)):
            orbit.addRow(label, w)
        layout.addWidget(self.orbit_box)

        self.sun_box = QtGui.QGroupBox("Fixed sun")
        sun = QtGui.QFormLayout(self.sun_box)
        d = e.SunDirection if e else None
        self.sun = [_spin(getattr(d, c) if d else (1.0 if c == "x" else 0.0), -1.0, 1.0, 3, "") for c in "xyz"]
        row = QtGui.QHBoxLayout()
        for w in self.sun:
            row.addWidget(w)
        sun.addRow("Direction to the sun (body axes)", row)
        self.flux = _quantity("%r W/m^2" % (e.SolarFlux if e else 1361.0), 0.0)
        sun.addRow("Solar flux", self.flux)
        layout.addWidget(self.sun_box)

        self.analysis_box = QtGui.QGroupBox("Analysis")
        run = QtGui.QFormLayout(self.analysis_box)
        self.type = _combo(["steady", "transient_orbit"], analysis.AnalysisType)
        self.steps = QtGui.QSpinBox()
        self.steps.setRange(4, 100000)
        self.steps.setValue(analysis.StepsPerOrbit)
        run.addRow("Type", self.type)
        run.addRow("Time steps per orbit", self.steps)
        layout.addWidget(self.analysis_box)
        self.kind.currentIndexChanged.connect(self._kind)
        self._kind()

    def _kind(self, *args):
        orbit = self.kind.currentText() == "orbit"
        self.orbit_box.setVisible(orbit)
        self.sun_box.setVisible(not orbit)

    def lines(self):
        """The script lines OK runs (one transaction)."""
        out = ["analysis = App.ActiveDocument.%s" % self.analysis.Name]
        out.append("env = App.ActiveDocument.%s" % self.env.Name if self.env is not None
                   else "env = tdo.makeEnvironment(analysis, %r)" % self.kind.currentText())
        out.append("env.EnvironmentType = %r" % self.kind.currentText())
        if self.kind.currentText() == "orbit":
            out += ["env.Altitude = '%r km'" % quantity_value(self.altitude, "km"),
                    "env.Inclination = %r" % quantity_value(self.inclination, "deg"),
                    "env.RAAN = %r" % quantity_value(self.raan, "deg"),
                    "env.DayOfYear = %d" % self.day.value(),
                    "env.Attitude = %r" % self.attitude.currentText(),
                    "env.Albedo = %r" % self.albedo.value(),
                    "env.EarthIRFlux = %r" % quantity_value(self.earth_ir, "W/m^2")]
        else:
            out += ["env.SunDirection = App.Vector(%r, %r, %r)" % tuple(w.value() for w in self.sun),
                    "env.SolarFlux = %r" % quantity_value(self.flux, "W/m^2")]
        out += ["analysis.AnalysisType = %r" % self.type.currentText(),
                "analysis.StepsPerOrbit = %d" % self.steps.value()]
        return out

    def accept(self):
        ok = gui_actions.run("Thermal environment", self.lines())
        if ok:
            FreeCADGui.Control.closeDialog()
        return ok


class ReducePanel(_Panel):
    """Reduce settings (tolerance, strategy, node merging, load cases, plots); OK stores them on the analysis
    (one transaction) and starts the reduction in the background (RunPanel)."""

    def __init__(self, analysis):
        ACTIVE[type(self).__name__] = self
        self.analysis = analysis
        self.form, layout = _form("Reduce")
        self.tolerance = _quantity("%r K" % analysis.ToleranceK, 0.0)
        self.strategy = _combo(["informed", "uniform"], analysis.ReductionStrategy)
        self.merge = QtGui.QCheckBox("merge nodes as well")
        self.merge.setChecked(bool(getattr(analysis, "MergeNodes", False)))
        self.merge.setToolTip("thermodec reduce --merge-nodes: nodes may be merged into isothermal nodes within the same tolerance; the reduced "
                              "model carries the node map and the tree lists each merged node with its members")
        self.cases = QtGui.QListWidget()
        self.cases.addItems(list(analysis.LoadCases))
        self.cases.setMaximumHeight(90)
        buttons = QtGui.QHBoxLayout()
        add, remove = QtGui.QPushButton("Add case..."), QtGui.QPushButton("Remove")
        add.clicked.connect(self._add_case)
        remove.clicked.connect(lambda: [self.cases.takeItem(self.cases.row(i)) for i in self.cases.selectedItems()])
        buttons.addWidget(add)
        buttons.addWidget(remove)
        self.plots = QtGui.QCheckBox("write the core's PNG plots")
        self.plots.setChecked(True)
        layout.addRow("Temperature tolerance", self.tolerance)
        layout.addRow("Strategy", self.strategy)
        layout.addRow("", self.merge)
        layout.addRow("Load cases", self.cases)
        layout.addRow("", buttons)
        layout.addRow("", self.plots)
        note = QtGui.QLabel("Runs `thermodec reduce` in the background: the dense model is simulated, "
                            "reduced to the tolerance (max |dT| over nodes and the orbit, verified by a "
                            "full recompute) and the reduced model simulated. Cancel stops it.")
        note.setWordWrap(True)
        layout.addRow(note)

    def _add_case(self):
        paths, _ = QtGui.QFileDialog.getOpenFileNames(FreeCADGui.getMainWindow(), "Load case", "",
                                                      "Load case (*.json)")
        self.cases.addItems(paths)

    def settings_lines(self):
        cases = [self.cases.item(k).text() for k in range(self.cases.count())]
        return ["analysis = App.ActiveDocument.%s" % self.analysis.Name,
                "analysis.ToleranceK = %r" % quantity_value(self.tolerance, "K"),
                "analysis.ReductionStrategy = %r" % self.strategy.currentText(),
                "analysis.MergeNodes = %r" % self.merge.isChecked(),
                "analysis.LoadCases = %r" % cases]

    def accept(self):
        plots = self.plots.isChecked()  # the form is gone once the dialog closes
        if not gui_actions.run("Reduce settings", self.settings_lines()):
            return False
        FreeCADGui.Control.closeDialog()
        start_reduce(self.analysis, plots=plots)
        return True


def _needs_mesh(analysis, then):
    """Without a ThermalMesh the analysis is tessellated first, in the background; `then()`
    starts the job asked for once the mesh is in. Returns True when that was started."""
    if analysis.ThermalMesh is not None:
        return False
    start_tessellate(analysis, then=then)
    return True


def start_tessellate(analysis, then=None):
    """Runs the tessellation in `freecadcmd` with a RunPanel (runner.tessellate_job); the mesh
    is stored when it ends (one transaction). `then()`: called after that, e.g. to go on with
    a simulation. Returns the panel (or None: the error is shown)."""
    return _start_job(analysis, None, "tessellate_job", ("tessellate", "import_job"), "Tessellate", then=then,
                      done=lambda: _tessellated(analysis))


def _tessellated(analysis):
    tm = analysis.ThermalMesh
    if tm is not None:
        gui_actions.status("ThermoDec: %d triangles, longest edge %.1f mm" % (tm.Mesh.CountFacets, tm.LongestEdge))


def start_reduce(analysis, plots=True):
    """Exports the analysis and runs the Reduce job in the background with a RunPanel.
    Returns the panel (or None when the job could not start: the error is shown)."""
    return _start_job(analysis, lambda: start_reduce(analysis, plots), "reduce_job",
                      ("results", "import_reduction"), "Import reduced model", plots=plots)


def start_simulate(analysis):
    """Exports the analysis and runs `thermodec simulate` in the background with a RunPanel;
    the result is imported when it ends. Returns the panel (or None: the error is shown)."""
    return _start_job(analysis, lambda: start_simulate(analysis), "simulate_job", ("results", "import_simulation"),
                      "Import simulation")


def start_decimate(analysis):
    """Exports the analysis and runs `thermodec decimate` (the analysis' GlobalRatio) in the
    background with a RunPanel; the reduced mesh is imported when it ends."""
    return _start_job(analysis, lambda: start_decimate(analysis), "decimate_job", ("results", "import_decimation"),
                      "Import decimated mesh")


def start_export(analysis, fmt, out):
    return _start_job(analysis, lambda: start_export(analysis, fmt, out), "export_job", None, "", fmt=fmt, out=out)


def _start_job(analysis, again, make, finish, finish_title, then=None, done=None, **args):
    """Builds runner.<make>(analysis, **args) and runs it with a RunPanel; `finish` = (module
    of thermodec_freecad, function) imports the outputs: function(analysis, job.outputs) as one
    transaction. Without a ThermalMesh the analysis is tessellated first and `again()` called
    after (`again` None: no mesh needed). Returns the panel, or None (the error is shown)."""
    if again is not None and analysis.ThermalMesh is None:
        return start_tessellate(analysis, then=again)
    from . import runner
    try:
        job = getattr(runner, make)(analysis, **args)
    except Exception as e:
        gui_actions.error(e)
        return None
    lines = []
    if finish:
        lines = ["analysis = App.ActiveDocument.%s" % analysis.Name, "import thermodec_freecad.%s as td%s" % (finish[0], finish[0]),
                 "td%s.%s(analysis, %r)" % (finish[0], finish[1], job.outputs)]
    return _start(job, lines, finish_title, then=then, done=done)


def _start(job, finish_lines, finish_title, then=None, done=None):
    panel = RunPanel(job, finish_lines, finish_title, then, done)
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    FreeCADGui.Control.showDialog(panel)
    panel.start()
    return panel


class RunPanel:
    """A background job (runner.Runner): step k of n, elapsed time, the CLI's output lines and
    Cancel. FreeCAD stays usable meanwhile. On success the finish lines import the results in
    one transaction; the output goes to the report view."""

    def __init__(self, job, finish_lines, finish_title, then=None, done=None):
        ACTIVE[type(self).__name__] = self
        from . import runner
        self.job, self.finish_lines, self.finish_title = job, finish_lines, finish_title
        self.then, self.after_import = then, done  # called after a successful import
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(job.title)
        layout = QtGui.QVBoxLayout(self.form)
        self.step = QtGui.QLabel()
        self.step.setWordWrap(True)
        self.bar = QtGui.QProgressBar()  # per step 100; within `reduce`, by its stage lines
        self.bar.setRange(0, 100 * len(job.steps))
        self.bar.setFormat("%p %")
        self.share = 0.0
        self.elapsed = QtGui.QLabel()
        self.log = QtGui.QPlainTextEdit()
        self.log.setReadOnly(True)
        self.log.setMinimumHeight(260)
        self.log.setLineWrapMode(QtGui.QPlainTextEdit.WidgetWidth)
        self.cancel_button = QtGui.QPushButton("Cancel")
        for w in (self.step, self.bar, self.elapsed, self.cancel_button, self.log):
            layout.addWidget(w)
        self.runner = runner.Runner(job, self._line, self._done)
        self.cancel_button.clicked.connect(self.runner.cancel)
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(self._tick)
        self.done, self.ok, self.message = False, False, ""

    def start(self):
        self.timer.start(500)
        self.runner.start()

    def _tick(self):
        import time
        self.elapsed.setText("elapsed %.0f s" % (time.monotonic() - self.runner.started))

    def _line(self, text):
        self.log.appendPlainText(text)
        bar = self.log.verticalScrollBar()
        bar.setValue(bar.maximum())  # follow the newest line
        from . import runner
        if text.startswith("[") and "/" in text.split("]")[0]:  # a step starts
            self.step.setText(text)
            self.share = 0.0
        share = runner.stage_fraction(text)
        if share is not None:
            self.share = max(self.share, share)
        self.bar.setValue(int(100 * (self.runner.index + self.share)))
        gui_actions.status("ThermoDec: %s" % text[:160])

    def _done(self, ok, message):
        import FreeCAD
        self.timer.stop()
        self._tick()
        if ok:
            self.bar.setValue(self.bar.maximum())
        FreeCAD.Console.PrintMessage("ThermoDec: %s\n%s\n" % (
            message, "\n".join(self.log.toPlainText().splitlines()[-30:])))
        if ok and self.finish_lines:
            ok = gui_actions.run(self.finish_title, self.finish_lines)
        self.done, self.ok, self.message = True, ok, message
        self.cancel_button.setEnabled(False)
        self.step.setText(message)
        gui_actions.status("ThermoDec: %s" % message)
        if not ok and not self.runner.cancelled:
            FreeCAD.Console.PrintError("ThermoDec: %s\n" % message)
        if ok and self.after_import:
            self.after_import()
        if ok and self.then:  # the job this one prepared (a simulation after the mesh)
            self.then()

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        """Close: cancels a running job (the process is killed), else closes the panel."""
        if not self.done:
            self.runner.cancel()
            return False
        FreeCADGui.Control.closeDialog()
        return True

    def accept(self):
        return self.reject()
