"""What the workbench's commands and task panels share (GUI only): the active analysis, the
selection as face references, and running script lines as one undoable transaction.

commands.py opens task panels and task panels run their edits through `run`; both import
this module, so neither imports the other at load time.
"""

import FreeCAD
import FreeCADGui

from . import objects


def active_analysis(doc=None):
    """The selected ThermalAnalysis (or the one holding a selected member), else the first."""
    doc = doc or FreeCAD.ActiveDocument
    if doc is None:
        return None
    for obj in FreeCADGui.Selection.getSelection(doc.Name):
        if objects.is_type(obj, objects.ThermalAnalysis):
            return obj
        parent = objects.find_analysis(obj)
        if parent is not None:
            return parent
    for obj in doc.Objects:
        if objects.is_type(obj, objects.ThermalAnalysis):
            return obj
    return None


def selected_faces():
    """[(object, [sub names])] of the selection: faces as picked, whole objects as ''."""
    refs = []
    for sel in FreeCADGui.Selection.getSelectionEx():
        obj = sel.Object
        if not hasattr(obj, "Shape") or obj.TypeId.startswith("Mesh::") or \
                getattr(getattr(obj, "Proxy", None), "Type", "").startswith("ThermoDec::"):
            continue
        subs = [s for s in sel.SubElementNames if s.startswith("Face")]
        refs.append((obj, subs or [""]))
    return refs


def refs_code(refs):
    return "[%s]" % ", ".join("(App.ActiveDocument.%s, %r)" % (obj.Name, list(subs)) for obj, subs in refs)


#: False in scripted GUI runs (gui_demo.py): errors are raised instead of shown in a
#: modal dialog that nobody would close.
SHOW_DIALOGS = True


def error(message):
    FreeCAD.Console.PrintError("ThermoDec: %s\n" % message)
    if not SHOW_DIALOGS:
        raise RuntimeError(str(message))
    from PySide import QtGui
    QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "ThermoDec", str(message))


def status(message):
    FreeCADGui.getMainWindow().statusBar().showMessage(message)
    from PySide import QtGui
    QtGui.QApplication.processEvents()


def run(title, lines):
    """Runs script lines in one undoable transaction; on error aborts and shows the message.
    Returns True on success."""
    doc = FreeCAD.ActiveDocument
    doc.openTransaction(title)
    try:
        FreeCADGui.doCommand("import thermodec_freecad.objects as tdo")
        for line in lines:
            FreeCADGui.doCommand(line)
        doc.recompute()
        doc.commitTransaction()
        return True
    except Exception as e:  # a dialog, never a traceback, for the user
        doc.abortTransaction()
        error(e)
        return False


def analysis_line():
    analysis = active_analysis()
    if analysis is None:
        raise RuntimeError("create a thermal analysis first")
    return "analysis = App.ActiveDocument.%s" % analysis.Name
