"""Opens FreeCAD's GUI in the ThermoDec workbench, from a build tree (docs/freecad.md):

  THERMODEC_PYTHON_DIR=$PWD/build/python freecad $PWD/freecad_workbench/start_thermodec.py \
      -M $PWD/freecad_workbench/ThermoDec

FreeCAD 0.20 hands its command line to its embedded Python first, which rejects `-M` as an
unknown option (and FreeCAD then crashes) unless a file name comes before it: this script is
that file. FreeCAD runs it once the GUI is up; further files (a .FCStd, a STEP) may follow it.

THERMODEC_START_CHECK=<file> (CTest): writes the active workbench and the thermodec module
found to <file>, then closes FreeCAD.
"""

import os

import FreeCAD
import FreeCADGui


def _start():
    FreeCADGui.activateWorkbench("ThermoDecWorkbench")
    try:
        import thermodec
        module = os.path.dirname(os.path.abspath(thermodec.__file__))
    except ImportError as e:
        module = "missing (%s): set THERMODEC_PYTHON_DIR to build/python" % e
        FreeCAD.Console.PrintWarning("ThermoDec: the thermodec module is %s\n" % module)
    check = os.environ.get("THERMODEC_START_CHECK")
    if check:
        with open(check, "w", encoding="utf-8") as f:
            f.write("workbench %s\nthermodec module %s\ncommands %d\n" % (
                FreeCADGui.activeWorkbench().name(), module,
                sum(1 for c in FreeCADGui.listCommands() if c.startswith("ThermoDec_"))))
        FreeCADGui.getMainWindow().close()


_start()
