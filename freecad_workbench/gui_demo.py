"""GUI walk-through of the ThermoDec workbench on the sample satellite, with screenshots.

  THERMODEC_PYTHON_DIR=build/python QTWEBENGINE_DISABLE_SANDBOX=1 \
      xvfb-run -a -s '-screen 0 1600x1000x24' freecad freecad_workbench/gui_demo.py \
      -M freecad_workbench/ThermoDec

Environment: THERMODEC_DEMO_REDUCE=1 (Reduce instead of Decimate), THERMODEC_DEMO_OUTPUT (folder for screenshots and the model; default
./thermodec_gui_demo), THERMODEC_PYTHON_DIR = the folder of the thermodec module (build/python;
FreeCAD's GUI ignores PYTHONPATH). `freecad script.py` always
exits 0, so the script writes DONE (or FAILED and the traceback) to status.txt there and
exits with os._exit(0 or 1).
"""

import os
import sys
import traceback

import FreeCAD as App
import FreeCADGui as Gui

OUT = os.path.abspath(os.environ.get("THERMODEC_DEMO_OUTPUT", "thermodec_gui_demo"))
#: THERMODEC_DEMO_REDUCE=1: run Reduce (simulation-driven, minutes) instead of Decimate
#: (seconds), on a coarser dense mesh with fewer rays so that it stays a few minutes.
REDUCE = os.environ.get("THERMODEC_DEMO_REDUCE") == "1"
MAX_EDGE_MM = 250.0 if REDUCE else 120.0
#: The shipped sample model, simulated as it is at the end of the walk-through.
#: THERMODEC_SAMPLE_MODEL overrides it (default: the checkout's sample_models/satellite/model.json).
SAMPLE_MODEL = os.environ.get("THERMODEC_SAMPLE_MODEL")


def process_events():
    from PySide import QtGui
    for _ in range(5):
        QtGui.QApplication.processEvents()


def wait_for_job(panel, timeout_s):
    """Runs the event loop until the background job of a RunPanel ends. Raises on failure."""
    import time
    from PySide import QtGui
    start = time.monotonic()
    while panel is not None and not panel.done and time.monotonic() - start < timeout_s:
        QtGui.QApplication.processEvents()
        time.sleep(0.02)
    if panel is None or not panel.ok:
        raise RuntimeError("background job: %s" % (panel.message if panel is not None else "not started"))


def screenshot(name):
    """Saves the 3D view, and the whole screen with `import -window root` (ImageMagick; a Qt
    grab of the main window leaves the OpenGL view blank)."""
    import shutil
    import subprocess
    view = Gui.ActiveDocument.ActiveView
    view.saveImage(os.path.join(OUT, name + "_view.png"), 1200, 800, "White")
    process_events()
    if shutil.which("import"):
        subprocess.run(["import", "-window", "root", os.path.join(OUT, name + "_window.png")], check=True)


def main():
    from thermodec_freecad import export, gui_actions, objects, sample, taskpanels
    from FreeCAD import Vector

    gui_actions.SHOW_DIALOGS = False
    os.makedirs(OUT, exist_ok=True)
    main_window = Gui.getMainWindow()
    main_window.showMaximized()
    Gui.activateWorkbench("ThermoDecWorkbench")
    doc = App.newDocument("Satellite")
    shapes = sample.build_shapes(doc)
    Gui.SendMsgToActiveView("ViewFit")

    # Create analysis (command), nodes per face of the body (command on the selection).
    Gui.runCommand("ThermoDec_Analysis")
    analysis = gui_actions.active_analysis(doc)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(shapes["Body"])
    Gui.runCommand("ThermoDec_AutoNodesPerFace")

    # Wings, boom and dish: one node each through the node task panel.
    for name in ("WingPlusY", "WingMinusY", "Boom", "Dish"):
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(shapes[name])
        panel = taskpanels.NodePanel(analysis, gui_actions.selected_faces())
        Gui.Control.showDialog(panel)
        panel.name.setText(name.lower())
        panel.capacitance.setValue(2000.0)
        assert panel.accept(), name
    process_events()

    # Coatings through the material task panel: MLI on the body nodes, solar cells on the
    # wing fronts, white paint as the analysis default.
    def material_to(coating, refs=(), nodes=()):
        panel = taskpanels.MaterialPanel(analysis, list(refs), list(nodes))
        Gui.Control.showDialog(panel)
        panel.choice.setCurrentIndex(sorted(objects.coatings.COATINGS).index(coating))
        assert panel.accept(), coating

    body_nodes = [n for n in objects.members(analysis, objects.ThermalNode) if n.Label.startswith("Body")]
    material_to("mli_outer_layer", nodes=body_nodes)
    for wing in ("WingPlusY", "WingMinusY"):
        top = sample._face_towards(shapes[wing], Vector(0, 0, 1))
        material_to("solar_cell", refs=[(shapes[wing], [top])])
    material_to("white_paint", nodes=[])  # creates the material...
    analysis.DefaultMaterial = [m for m in objects.members(analysis, objects.ThermalMaterial)
                                if m.Coating == "white_paint"][0]  # ...and makes it the default
    Gui.runCommand("ThermoDec_Environment")  # opens the environment panel: the default orbit
    assert taskpanels.ACTIVE["EnvironmentPanel"].accept(), "environment"
    if REDUCE:
        analysis.RaysPerFace = 400

    # Tessellate through its task panel, then export.
    panel = taskpanels.TessellatePanel(analysis)
    Gui.Control.showDialog(panel)
    panel.length.setValue(MAX_EDGE_MM)
    assert panel.accept(), "tessellate"
    wait_for_job(taskpanels.ACTIVE.get("RunPanel"), 300)  # meshed in the background (freecadcmd)
    Gui.Control.closeDialog()
    for obj in shapes.values():
        obj.ViewObject.Visibility = False
    analysis.ThermalMesh.ViewObject.DisplayMode = "Flat Lines"
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(analysis.ThermalMesh)  # expands the analysis in the tree
    process_events()
    Gui.Selection.clearSelection()  # selection would paint the mesh green
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    process_events()
    screenshot("tessellated_by_node")

    # Export, simulate (command: status-bar progress, temperature colours), decimate.
    analysis.OutputDirectory = os.path.join(OUT, "model")
    json_path, mesh_path = export.write_model(analysis, os.path.join(OUT, "model", "model.json"))
    Gui.runCommand("ThermoDec_Simulate")  # in the background (thermodec simulate), a progress panel
    wait_for_job(taskpanels.ACTIVE.get("RunPanel"), 300)
    Gui.Control.closeDialog()
    process_events()
    if not analysis.ResultFile:
        raise RuntimeError("simulation did not run (is the thermodec module on THERMODEC_PYTHON_DIR?)")
    screenshot("simulated_dense")
    if REDUCE:  # the simulation-driven reduction (Reduce command, no dialog)
        analysis.ToleranceK = 1.0  # in-process here; the Reduce command runs it in the background
        assert gui_actions.run("Reduce", ["analysis = App.ActiveDocument.%s" % analysis.Name,
                                          "import thermodec_freecad.results as tdresults",
                                          "tdresults.reduce(analysis)"]), "reduce"
    else:  # quick: decimation to a fixed ratio (the command: `thermodec decimate` in the background)
        from PySide import QtGui
        QtGui.QInputDialog.getDouble = staticmethod(lambda *a, **k: (0.9, True))  # the ratio asked for
        Gui.runCommand("ThermoDec_Decimate")
        wait_for_job(taskpanels.ACTIVE.get("RunPanel"), 300)
        Gui.Control.closeDialog()
    reduced = doc.getObject("ReducedMesh")
    if reduced is None:
        raise RuntimeError("no reduced mesh: the Reduce/Decimate step failed (see the report view)")
    analysis.ThermalMesh.ViewObject.Visibility = False
    reduced.ViewObject.DisplayMode = "Flat Lines"
    Gui.SendMsgToActiveView("ViewFit")
    process_events()
    screenshot("reduced")
    sample_result = simulate_sample(doc, analysis, reduced)
    doc.saveAs(os.path.join(OUT, "satellite.FCStd"))
    from thermodec_freecad import temperature_field, thermal_result
    tm = analysis.ThermalMesh
    t = tm.FaceTemperature
    with open(os.path.join(OUT, "summary.txt"), "w") as f:
        f.write("dense: %d triangles, %d vertices, %d nodes, longest edge %.1f mm\n" % (
            tm.Mesh.CountFacets, tm.Mesh.CountPoints, len(tm.NodeNames), tm.LongestEdge))
        f.write("node mean temperatures %.1f K .. %.1f K\n" % (min(t), max(t)))
        f.write("reduced (%s): %d triangles\nmodel %s\nresult %s\n" % (
            "Reduce, tolerance %g K" % analysis.ToleranceK if REDUCE else "Decimate 0.9",
            reduced.Mesh.CountFacets, json_path, analysis.ResultFile))
        mesh, res = sample_result
        rows = temperature_field.statistics_table(*thermal_result.matrix(res)[::2])
        f.write("sample %s: %d triangles, %d nodes, seed %d, %d rays per face, %d times; colour bar (%s) "
                "%.2f K .. %.2f K\n" % (res.ResultFile, mesh.Mesh.CountFacets, len(rows), res.Seed, res.RaysPerFace,
                                        len(res.TimesS), res.Shown, res.ColourMinK, res.ColourMaxK))
        for row in rows:
            f.write("  %-12s min %.2f K  mean %.2f K  max %.2f K\n" % row)
        report = os.path.join(OUT, "model", "reduced", "report.json")
        if REDUCE and os.path.exists(report):
            import json
            with open(report) as r:
                data = json.load(r)
            f.write("report: %s\n" % json.dumps({k: data[k] for k in (
                "faces_before", "faces_after", "max_temperature_difference_K", "noise_floor_K",
                "tolerance_K") if k in data}))


def simulate_sample(doc, analysis, reduced):
    """The shipped sample model (sample_models/satellite, 882 triangles, 13 nodes) simulated as
    it is (orbit, transient), shown with its colour bar and the result panel: the mean over the
    orbit, then one time step in sunlight. Returns (mesh, ThermalResult)."""
    import thermodec_freecad
    from thermodec_freecad import gui_actions, objects, taskpanels, thermal_result
    sample = SAMPLE_MODEL or os.path.join(os.path.dirname(thermodec_freecad.__file__), os.pardir, os.pardir,
                                          os.pardir, "sample_models", "satellite", "model.json")
    assert gui_actions.run("Simulate model file", [
        "analysis = App.ActiveDocument.%s" % analysis.Name,
        "import thermodec_freecad.results as tdresults",
        "tdresults.simulate_model_file(analysis, %r)" % os.path.abspath(sample)]), "simulate sample"
    mesh = doc.getObject("SimulatedMesh")
    result = [r for r in objects.members(analysis, thermal_result.ThermalResult) if r.ResultMesh == mesh][0]
    for obj in (analysis.ThermalMesh, reduced):
        obj.ViewObject.Visibility = False
    mesh.ViewObject.DisplayMode = "Flat Lines"
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    process_events()
    screenshot("sample_mean")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(result)
    Gui.runCommand("ThermoDec_ShowResult")  # the command opens the result panel (setEdit) ...
    process_events()
    if not Gui.Control.activeDialog():
        raise RuntimeError("the Thermal result command opened no panel")
    Gui.ActiveDocument.resetEdit()
    Gui.Selection.clearSelection()
    panel = taskpanels.ResultPanel(result)  # ... opened here by hand to drive its controls
    Gui.Control.showDialog(panel)
    from PySide import QtCore, QtGui
    window = Gui.getMainWindow()
    docks = [d for d in window.findChildren(QtGui.QDockWidget) if d.windowTitle() == "Combo View"]
    window.resizeDocks(docks, [430] * len(docks), QtCore.Qt.Horizontal)  # the whole table in view
    Gui.SendMsgToActiveView("ViewFit")
    process_events()
    screenshot("sample_result_panel")
    panel.field.setCurrentIndex(3)  # one time step: the hottest moment of the +Y wing
    nodes, times, T = thermal_result.matrix(result)
    panel.step.setValue(int(T[nodes.index("wing_py")].argmax()))
    process_events()
    screenshot("sample_time_step")
    assert panel.accept(), "result panel"
    process_events()
    return mesh, result


def run():
    status = os.path.join(OUT, "status.txt")
    os.makedirs(OUT, exist_ok=True)
    try:
        main()
        with open(status, "w") as f:
            f.write("DONE\n")
        code = 0
    except Exception:
        with open(status, "w") as f:
            f.write("FAILED\n" + traceback.format_exc())
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    os._exit(code)


run()
