"""What the FreeCAD GUI tests share (gui_workflow.py, gui_model_file.py): the output folder and
its status file, the event loop, screenshots, dialogs answered the way a user would, the task
panel shown now and the wait for a background job.

`freecad script.py` exits 0 whatever happens: `run(main)` writes DONE or FAILED and the
traceback (then the notes) to status.txt in THERMODEC_GUI_OUTPUT and leaves with os._exit.
"""

import os
import subprocess
import sys
import time
import traceback

import FreeCAD as App

OUT = os.path.abspath(os.environ.get("THERMODEC_GUI_OUTPUT", "thermodec_gui_test"))
LOG = []
NAME = "gui test"  #: the notes' prefix in the report view; each script sets its own


def note(text):
    LOG.append(text)
    App.Console.PrintMessage("%s: %s\n" % (NAME, text))


def events(n=5):
    from PySide import QtGui
    for _ in range(n):
        QtGui.QApplication.processEvents()


def screenshot(name, settle_s=0.0):
    """The whole screen (`import -window root`, ImageMagick: a Qt grab leaves the 3D view
    blank) as OUT/name.png. `settle_s`: event-loop time first (the property view follows the
    selection on a timer)."""
    start = time.monotonic()
    events(10)
    while time.monotonic() - start < settle_s:
        events(2)
        time.sleep(0.02)
    subprocess.run(["import", "-window", "root", os.path.join(OUT, name + ".png")], check=True)


def patch_dialogs(open_file=None, save_file=None, item=None):
    """Answers the next file / item dialogs the way a user would."""
    from PySide import QtGui
    if open_file:
        QtGui.QFileDialog.getOpenFileName = staticmethod(lambda *a, **k: (open_file, ""))
    if save_file:
        QtGui.QFileDialog.getSaveFileName = staticmethod(lambda *a, **k: (save_file, ""))
    if item:
        QtGui.QInputDialog.getItem = staticmethod(lambda *a, **k: (item, True))


def wide_combo_view(window, width=430):
    """The Combo View (tree and task panels) `width` pixels wide: the panels' values readable."""
    from PySide import QtCore, QtGui
    docks = [d for d in window.findChildren(QtGui.QDockWidget) if d.windowTitle() == "Combo View"]
    window.resizeDocks(docks, [width] * len(docks), QtCore.Qt.Horizontal)
    events()


def active_panel(cls):
    """The task panel of class `cls` shown now (FreeCAD hands back only its form)."""
    from thermodec_freecad import taskpanels
    panel = taskpanels.ACTIVE.get(cls.__name__)
    if panel is None:
        raise RuntimeError("no %s open" % cls.__name__)
    return panel


def wait_for(panel, timeout_s, shot=None, shot_after_s=4):
    """Lets the event loop run until the background job of a RunPanel ends; the GUI stays live
    meanwhile (counted: event-loop turns while the job runs). Optionally a screenshot mid-run.
    Returns the turns; raises when the job failed or outlived timeout_s (then cancelled)."""
    from PySide import QtGui
    start, turns, shot_taken = time.monotonic(), 0, False
    while not panel.done:
        QtGui.QApplication.processEvents()
        turns += 1
        time.sleep(0.02)
        if shot and not shot_taken and time.monotonic() - start > shot_after_s:
            screenshot(shot)
            shot_taken = True
        if time.monotonic() - start > timeout_s:
            panel.runner.cancel()
            raise RuntimeError("%s still running after %d s" % (panel.job.title, timeout_s))
    note("%s: %s (%d event-loop turns while it ran, %.0f s)" % (panel.job.title, panel.message, turns,
                                                             time.monotonic() - start))
    if not panel.ok:
        raise RuntimeError(panel.message)
    return turns


def run(main):
    """Runs main(), writes OUT/status.txt and leaves FreeCAD (exit code 0 or 1)."""
    status = os.path.join(OUT, "status.txt")
    os.makedirs(OUT, exist_ok=True)
    try:
        main()
        text, code = "DONE\n", 0
    except Exception:
        text, code = "FAILED\n" + traceback.format_exc(), 1
        traceback.print_exc()
    with open(status, "w") as f:
        f.write(text + "\n".join(LOG) + "\n")
    sys.stdout.flush()
    os._exit(code)
