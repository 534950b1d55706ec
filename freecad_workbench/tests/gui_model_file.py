"""GUI test: a model file opened in the real FreeCAD (Open model file), under Xvfb.

  THERMODEC_PYTHON_DIR=build/python THERMODEC_CLI=build/core/thermodec THERMODEC_GUI_OUTPUT=/tmp/gui \
      QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a -s '-screen 0 1600x1000x24' freecad \
      freecad_workbench/tests/gui_model_file.py -M freecad_workbench/ThermoDec

1. The sample satellite with merged nodes (`thermodec merge`): Open model file (command, file
   dialog answered); the tree lists each merged node under the model's mesh with its members,
   read from the tree widget itself; screenshot merged_tree.png.
2. The sample around the Moon with a power schedule and a heater: Open model file, then Export
   model (command, dialog answered) writes them back; the heater node's kept keys in the
   property editor; screenshot kept_keys.png.
status.txt in THERMODEC_GUI_OUTPUT says DONE or FAILED (gui_helpers.run).
"""

import json
import os
import subprocess
import sys

import FreeCAD as App
import FreeCADGui as Gui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gui_helpers  # noqa: E402
from gui_helpers import OUT, events, note, patch_dialogs, wide_combo_view  # noqa: E402

gui_helpers.NAME = "gui_model_file"
SAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "sample_models",
                      "satellite", "model.json")


def screenshot(name):
    gui_helpers.screenshot(name, settle_s=0.5)  # the property view follows the selection on a timer


def tree_children(label):
    """Texts of the children of the tree item labelled `label` in FreeCAD's model tree."""
    from PySide import QtGui
    for tree in Gui.getMainWindow().findChildren(QtGui.QTreeWidget):
        for item in tree.findItems(label, QtCore_flags(), 0):
            return [item.child(i).text(0) for i in range(item.childCount())]
    return None


def show_in_tree(path, obj, scroll_to=None):
    """Expands the tree along `path` (item labels: document, analysis, ...), selects `obj` (its
    last item) and scrolls to the item labelled `scroll_to` (default: the same)."""
    from PySide import QtGui
    tree = [t for t in Gui.getMainWindow().findChildren(QtGui.QTreeWidget) if t.findItems(path[0], QtCore_flags(), 0)][0]
    for label in path:
        found = tree.findItems(label, QtCore_flags(), 0)
        assert found, "no tree item %r (path %s)" % (label, path)
        found[0].setExpanded(True)
        events(5)
    Gui.Selection.clearSelection()
    tree.setCurrentItem(found[0])  # a click: selects a claimed child (a merged node under its mesh)
    events(10)
    if not Gui.Selection.getSelection():  # a group member (a node) is selected by name
        Gui.Selection.addSelection(obj.Document.Name, obj.Name)
        events(10)
    assert [o.Name for o in Gui.Selection.getSelection()] == [obj.Name], Gui.Selection.getSelection()
    tree.scrollToItem(tree.findItems(scroll_to or path[-1], QtCore_flags(), 0)[0])
    events(10)


def QtCore_flags():
    from PySide import QtCore
    return QtCore.Qt.MatchExactly | QtCore.Qt.MatchRecursive


def merged_nodes_in_the_tree(window, cli):
    from thermodec_freecad import merged_nodes
    merged = os.path.join(OUT, "merged", "model.json")
    os.makedirs(os.path.dirname(merged), exist_ok=True)
    subprocess.run([cli, "merge", SAMPLE, "--group", "body_px,body_py,body_pz", "--group", "wing_py,wing_my",
                    "-o", merged], check=True, stdout=subprocess.DEVNULL)
    patch_dialogs(open_file=merged)
    Gui.runCommand("ThermoDec_OpenModel")
    doc = App.ActiveDocument
    mesh = doc.getObject("ThermalMesh")
    assert mesh is not None and len(mesh.MergedNodes) == 2, "opened: %s" % [o.Label for o in doc.Objects]
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    analysis = mesh.InList[0]
    show_in_tree([doc.Label, analysis.Label, mesh.Label, mesh.MergedNodes[0].Label], mesh.MergedNodes[0],
                 scroll_to=mesh.MergedNodes[-1].Label)
    shown = tree_children(mesh.Label)
    expected = [merged_nodes.label("body_px+2", ["body_px", "body_py", "body_pz"]),
                merged_nodes.label("wing_py+1", ["wing_py", "wing_my"])]
    assert shown == expected, "tree under %s: %s" % (mesh.Label, shown)
    screenshot("merged_tree")
    note("tree under %s: %s" % (mesh.Label, "; ".join(shown)))


def kept_keys_written_back(window):
    from thermodec_freecad import objects
    with open(SAMPLE) as f:
        data = json.load(f)
    data["mesh"] = os.path.join(os.path.dirname(os.path.abspath(SAMPLE)), data["mesh"])
    data["environment"]["central_body"] = "moon"
    del data["environment"]["albedo"], data["environment"]["earth_ir_flux"]
    del data["nodes"]["body_px"]["power"]
    data["nodes"]["body_px"]["power_schedule_W"] = [[0, 5.0], [1500.0, 45.0]]
    data["nodes"]["instrument"]["heater"] = {"on_K": 250.0, "off_K": 260.0, "power_W": 12.0}
    path = os.path.join(OUT, "moon", "model.json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    App.closeDocument(App.ActiveDocument.Name)
    patch_dialogs(open_file=path)
    Gui.runCommand("ThermoDec_OpenModel")
    doc = App.ActiveDocument
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    saved = os.path.join(OUT, "moon_saved", "model.json")
    patch_dialogs(save_file=saved)
    Gui.runCommand("ThermoDec_Export")
    with open(saved) as f:
        back = json.load(f)
    assert back["environment"] == data["environment"], back["environment"]
    assert back["nodes"]["instrument"]["heater"] == data["nodes"]["instrument"]["heater"]
    assert back["nodes"]["body_px"]["power_schedule_W"] == data["nodes"]["body_px"]["power_schedule_W"]
    assert "power" not in back["nodes"]["body_px"]
    node = doc.getObjectsByLabel("instrument")[0]
    assert objects.is_type(node, objects.ThermalNode)
    show_in_tree([doc.Label, node.InList[0].Label, "instrument"], node)  # the property editor shows its kept keys
    screenshot("kept_keys")
    note("written back: central_body %s, heater %s, schedule %s" % (
        back["environment"]["central_body"], back["nodes"]["instrument"]["heater"],
        back["nodes"]["body_px"]["power_schedule_W"]))


def main():
    from thermodec_freecad import gui_actions, runner
    gui_actions.SHOW_DIALOGS = False
    os.makedirs(OUT, exist_ok=True)
    window = Gui.getMainWindow()
    window.showMaximized()
    Gui.activateWorkbench("ThermoDecWorkbench")
    wide_combo_view(window, 520)
    cli = runner.cli_path()
    merged_nodes_in_the_tree(window, cli)
    kept_keys_written_back(window)


gui_helpers.run(main)
