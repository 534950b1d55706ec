"""GUI test: a user's whole flow through the ThermoDec workbench in the real FreeCAD, under Xvfb.

  THERMODEC_PYTHON_DIR=build/python THERMODEC_GUI_OUTPUT=/tmp/gui QTWEBENGINE_DISABLE_SANDBOX=1 \
      xvfb-run -a -s '-screen 0 1600x1000x24' freecad freecad_workbench/tests/gui_workflow.py \
      -M freecad_workbench/ThermoDec

Import STEP (command, file dialog answered) -> automatic nodes per face (command: default panel
heat capacity and edge links) -> material (task panel) -> environment (task panel) ->
tessellate (task panel, in the background: a fine run cancelled) -> simulate (command, in the background:
the mesh made first, then the simulation) -> reduce with node merging (task panel, run in
the background while the GUI keeps processing events; progress panel; the merged nodes in the
tree under the reduced mesh) -> plots (dock) -> export the reduced
model for NASTRAN (command, in the background) -> an edit marks the results stale -> save
elsewhere and reopen. Screenshots (`import -window root`) of each stage go to
THERMODEC_GUI_OUTPUT; status.txt there says DONE or FAILED (gui_helpers.run).
"""

import os
import sys
import time

import FreeCAD as App
import FreeCADGui as Gui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gui_helpers  # noqa: E402
from gui_helpers import OUT, active_panel, events, note, patch_dialogs, screenshot, wait_for, wide_combo_view  # noqa: E402

gui_helpers.NAME = "gui_workflow"


def make_step(path):
    """A two-solid box satellite as a STEP file: a 1 m body and a 0.4 m box on its +Z face."""
    import Part
    from FreeCAD import Vector
    shape = Part.makeCompound([Part.makeBox(1000, 1000, 1000, Vector(-500, -500, -500)),
                               Part.makeBox(400, 400, 400, Vector(-200, -200, 520))])
    shape.exportStep(path)


def main():
    import thermodec
    from thermodec_freecad import gui_actions, objects, plots, taskpanels, thermal_result
    from PySide import QtCore, QtGui
    gui_actions.SHOW_DIALOGS = False
    os.makedirs(OUT, exist_ok=True)
    window = Gui.getMainWindow()
    window.showMaximized()
    Gui.activateWorkbench("ThermoDecWorkbench")
    os.makedirs(os.path.join(OUT, "work"), exist_ok=True)
    os.chdir(os.path.join(OUT, "work"))
    step = os.path.join(OUT, "two_box_sat.step")
    make_step(step)

    # 1. Import STEP (the command; its file dialog answered).
    doc = App.newDocument("TwoBoxSat")
    patch_dialogs(open_file=step)
    Gui.runCommand("ThermoDec_ImportStep")
    sat = [o for o in doc.Objects if o.TypeId == "Part::Feature"][0]
    assert len(sat.Shape.Solids) == 2, "STEP import"
    wide_combo_view(window)
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    note("imported %s: %d solids, %d faces" % (step, len(sat.Shape.Solids), len(sat.Shape.Faces)))

    # 2. Analysis and automatic nodes per face (default panel capacity and edge links).
    Gui.runCommand("ThermoDec_Analysis")
    analysis = gui_actions.active_analysis(doc)
    assert not analysis.OutputDirectory  # outputs beside the document; unsaved: in the working folder
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(sat)
    Gui.runCommand("ThermoDec_AutoNodesPerFace")
    nodes = objects.members(analysis, objects.ThermalNode)
    links = objects.members(analysis, objects.Conductance)
    assert len(nodes) == 12 and all(n.Capacitance > 0 for n in nodes), "automatic nodes"
    note("%d nodes (%.0f .. %.0f J/K), %d links" % (len(nodes), min(n.Capacitance for n in nodes),
                                                   max(n.Capacitance for n in nodes), len(links)))

    # 3. Material through its task panel: white paint on every node.
    Gui.Selection.clearSelection()
    panel = taskpanels.MaterialPanel(analysis, [], nodes)
    Gui.Control.showDialog(panel)
    panel.choice.setCurrentIndex(sorted(objects.coatings.COATINGS).index("white_paint"))
    assert panel.accept(), "material"

    # 4. Environment through its task panel (the command opens it): a transient orbit.
    Gui.runCommand("ThermoDec_Environment")
    panel = Gui.Control.activeDialog() and active_panel(taskpanels.EnvironmentPanel)
    panel.altitude.setProperty("value", App.Units.Quantity("600 km"))
    panel.inclination.setProperty("value", App.Units.Quantity("98 deg"))
    panel.type.setCurrentIndex(1)  # transient_orbit
    panel.steps.setValue(24)
    events()
    screenshot("environment_panel")
    assert panel.accept(), "environment"
    env = objects.members(analysis, objects.Environment)[0]
    assert abs(env.Altitude.getValueAs("km") - 600) < 1e-9 and analysis.AnalysisType == "transient_orbit"
    analysis.RaysPerFace = 100

    # 5. Tessellate through its task panel: meshed in the background (freecadcmd) with a progress
    # panel. A first run at 8 mm edges (about 200 000 triangles) is cancelled after 3 s, the
    # event loop counted meanwhile: nothing is stored.
    panel = taskpanels.TessellatePanel(analysis)
    Gui.Control.showDialog(panel)
    panel.length.setValue(8.0)
    assert panel.accept(), "tessellate settings"
    run_panel = active_panel(taskpanels.RunPanel)
    start, turns = time.monotonic(), 0
    while time.monotonic() - start < 3 and not run_panel.done:
        events(1)
        turns += 1
        time.sleep(0.02)
    screenshot("tessellate_running")
    assert not run_panel.done, "an 8 mm tessellation ended within 3 s: %s" % run_panel.message
    assert turns > 50, "the GUI processed its events %d times in 3 s of tessellation" % turns
    run_panel.cancel_button.click()
    start = time.monotonic()
    while not run_panel.done and time.monotonic() - start < 30:
        events(1)
    assert run_panel.done and "cancelled" in run_panel.message, run_panel.message
    assert analysis.ThermalMesh is None, "a cancelled tessellation stored a mesh"
    note("tessellation at 8 mm: %d event-loop turns in 3 s, then %s" % (turns, run_panel.message))
    Gui.Control.closeDialog()

    # 6. Simulate (command) on the analysis left without a mesh: it tessellates first (the edge
    # length set to 250 mm as in the property editor), then runs `thermodec simulate`, each in the
    # background with its progress panel.
    assert gui_actions.run("Max edge length", ["App.ActiveDocument.%s.MaxEdgeLength = '250 mm'" % analysis.Name])
    Gui.runCommand("ThermoDec_Simulate")
    first = active_panel(taskpanels.RunPanel)
    assert first.job.title == "Tessellate", first.job.title
    wait_for(first, 240)
    assert analysis.ThermalMesh is not None and analysis.ThermalMesh.LongestEdge <= 250.0, "tessellate"
    then = active_panel(taskpanels.RunPanel)
    assert then is not first and then.job.title == "Simulate", then.job.title
    wait_for(then, 240)
    Gui.Control.closeDialog()
    dense = plots._result_on(analysis, "ThermalMesh")
    assert dense is not None and not dense.Stale, "simulate"
    _, _, T = thermal_result.matrix(dense)
    note("simulated: %d triangles, %.1f .. %.1f K" % (analysis.ThermalMesh.Mesh.CountFacets, T.min(), T.max()))
    assert T.min() > 100.0, "a node below 100 K"
    sat.ViewObject.Visibility = False
    analysis.ThermalMesh.ViewObject.DisplayMode = "Flat Lines"
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    screenshot("tessellated")

    # 7. Reduce through its task panel: runs in the background with a progress panel. A first
    # run is cancelled after a few seconds: nothing is imported.
    Gui.runCommand("ThermoDec_Reduce")
    assert active_panel(taskpanels.ReducePanel).accept(), "reduce settings"
    run_panel = active_panel(taskpanels.RunPanel)
    start = time.monotonic()
    while time.monotonic() - start < 3:
        events(1)
        time.sleep(0.02)
    run_panel.cancel_button.click()
    start = time.monotonic()
    while not run_panel.done and time.monotonic() - start < 30:
        events(1)
    assert run_panel.done and not run_panel.ok and "cancelled" in run_panel.message, run_panel.message
    assert doc.getObject("ReducedMesh") is None and not analysis.ReducedModelFile, "a cancelled run imported"
    note("cancelled: %s" % run_panel.message)
    Gui.Control.closeDialog()
    Gui.runCommand("ThermoDec_Reduce")
    panel = active_panel(taskpanels.ReducePanel)
    panel.tolerance.setProperty("value", App.Units.Quantity("3 K"))
    panel.merge.setChecked(True)  # nodes may be merged as well (--merge-nodes)
    screenshot("reduce_panel")
    assert panel.accept(), "reduce settings"
    wide_combo_view(window)  # the progress log readable
    run_panel = active_panel(taskpanels.RunPanel)
    turns = wait_for(run_panel, 420, shot="reduce_running", shot_after_s=15)  # past the node merging
    assert turns > 50, "the GUI did not process events while reducing"
    assert run_panel.bar.value() == run_panel.bar.maximum(), "progress %d of %d" % (
        run_panel.bar.value(), run_panel.bar.maximum())
    screenshot("reduce_done")
    Gui.Control.closeDialog()
    reduced = doc.getObject("ReducedMesh")
    assert reduced is not None and analysis.ReducedModelFile, "reduced model imported"
    analysis.ThermalMesh.ViewObject.Visibility = False
    reduced.ViewObject.DisplayMode = "Flat Lines"
    Gui.SendMsgToActiveView("ViewFit")
    note("reduced: %d -> %d triangles" % (analysis.ThermalMesh.Mesh.CountFacets, reduced.Mesh.CountFacets))
    # Merged nodes in the tree: under ReducedMesh, each with its members (the dense nodes).
    merged = list(reduced.MergedNodes) if "MergedNodes" in reduced.PropertiesList else []
    assert merged, "no merged node under ReducedMesh (node_map: %s)" % plots._node_map(analysis.ReducedModelFile)
    for m in merged:
        assert [n.Label for n in m.MemberNodes] == list(m.Members) and m.Label.startswith(m.MergedName + " (merged: ")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, merged[0].Name)  # expands ReducedMesh in the tree
    events(10)
    screenshot("reduce_merged_tree")
    note("merged nodes: %s" % "; ".join(m.Label for m in merged))

    # 8. Plots (command): a dock with temperatures over the orbit and the sensitivity curves.
    Gui.runCommand("ThermoDec_Plots")
    events(10)
    dock = window.findChild(QtGui.QDockWidget, plots.DOCK_NAME)
    if dock is None:  # the command failed: show why
        plots.PlotDock(analysis)
        raise RuntimeError("the Thermal plots command opened no dock")
    assert dock.isVisible(), "plot dock"
    combo = dock.findChild(QtGui.QComboBox)
    series = plots.orbit_series(analysis)  # the node the reduction moved most: original vs reduced
    assert series["reduced"] is not None and series["merged_into"], "merged nodes not plotted"
    worst = int(abs(series["reduced"] - series["dense"]).max(axis=1).argmax())
    combo.setCurrentIndex(1 + worst)
    screenshot("plots_temperatures")
    dock.findChild(QtGui.QTabWidget).setCurrentIndex(1)
    screenshot("plots_sensitivity")
    dock.findChild(QtGui.QTabWidget).setCurrentIndex(0)

    # 9. Export for other tools (command): the reduced model, in the background.
    bdf = os.path.join(OUT, "export", "reduced.bdf")
    os.makedirs(os.path.dirname(bdf), exist_ok=True)
    patch_dialogs(save_file=bdf, item="nastran")
    Gui.runCommand("ThermoDec_ExportTool")
    wait_for(active_panel(taskpanels.RunPanel), 240)
    Gui.Control.closeDialog()
    back = thermodec.load_model(bdf)
    assert back.mesh.num_faces == reduced.Mesh.CountFacets, "export wrote %d faces, reduced mesh has %d" % (
        back.mesh.num_faces, reduced.Mesh.CountFacets)
    note("exported %s: %d faces (the reduced model)" % (bdf, back.mesh.num_faces))

    # 10. Save elsewhere with the default output folder: the outputs follow; reopen.
    saved = os.path.join(OUT, "saved", "two_box_sat.FCStd")
    os.makedirs(os.path.dirname(saved), exist_ok=True)
    doc.saveAs(saved)
    name = doc.Name
    App.closeDocument(name)
    doc = App.openDocument(saved)
    events(20)
    analysis = [o for o in doc.Objects if objects.is_type(o, objects.ThermalAnalysis)][0]
    for prop in ("ModelFile", "ResultFile", "ReducedModelFile"):
        path = getattr(analysis, prop)
        assert path.startswith(os.path.dirname(saved)) and os.path.exists(path), "%s = %s" % (prop, path)
    results = objects.members(analysis, thermal_result.ThermalResult)
    assert len(results) == 2 and not any(r.Stale for r in results), [(r.Label, r.Stale) for r in results]
    analysis.ThermalMesh.ViewObject.Visibility = False
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    Gui.runCommand("ThermoDec_Plots")  # the reopened results, plotted again
    Gui.Selection.addSelection(doc.Name, results[-1].Name)  # expands the analysis in the tree
    events(10)
    screenshot("reopened")
    note("saved and reopened %s: paths beside it, %d results current" % (saved, len(results)))

    # 11. An input edit marks the results stale (labels in the tree say so).
    node = objects.members(analysis, objects.ThermalNode)[0]
    node.Capacitance = node.Capacitance * 2
    assert all(r.Stale and r.Label.endswith("(stale)") for r in objects.members(analysis, thermal_result.ThermalResult))
    title = plots._current.orbit_figure.axes[0].get_title()
    assert "(stale" in title, "plot title %r" % title
    screenshot("stale")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, results[-1].Name)
    Gui.runCommand("ThermoDec_ShowResult")  # the result panel says so too
    events(10)
    texts = [w.text() for w in active_panel(taskpanels.ResultPanel).form.findChildren(QtGui.QLabel)]
    assert any("STALE: Capacitance of" in t for t in texts), texts
    Gui.ActiveDocument.resetEdit()
    note("capacitance edited: results marked stale")


gui_helpers.run(main)
