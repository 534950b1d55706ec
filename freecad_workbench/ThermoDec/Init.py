# ThermoDec workbench, application part (loaded by FreeCAD and freecadcmd at start-up).
# The document objects live in thermodec_freecad/; nothing to register headless beyond the
# module path: FreeCAD already puts this folder (and the installed thermodec module beside
# it) on sys.path.
