# ThermoDec workbench, application part (run by FreeCAD and freecadcmd at start-up).
# The document objects live in thermodec_freecad/. FreeCAD puts this folder on sys.path, and
# an installed thermodec module sits in it. Run from a build tree, the module is in
# build/python: FreeCAD's GUI empties PYTHONPATH, so THERMODEC_PYTHON_DIR names that folder.
import os as _os
import sys as _sys

_dir = _os.environ.get("THERMODEC_PYTHON_DIR")
if _dir and _dir not in _sys.path:
    _sys.path.insert(0, _dir)

# Register the workbench's tests with FreeCAD's Test framework (Test workbench, `freecadcmd -t 0`
# runs every registered unit). TestThermoDec imports no GUI module, so it runs headless too.
import FreeCAD as _FreeCAD

_FreeCAD.__unit_test__ += ["TestThermoDec"]

# Outputs beside the document follow it when it is saved somewhere new (objects.follow_save).
import thermodec_freecad.objects as _objects

_FreeCAD.addDocumentObserver(_objects.SaveObserver())
