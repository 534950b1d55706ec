"""GUI commands of the ThermoDec workbench.

Each command runs its work as Python console lines (FreeCADGui.doCommand) inside a document
transaction: every action is undoable and shows up as a replayable script line. Errors are
shown in a dialog with the workbench's message.
"""

import FreeCAD
import FreeCADGui

from . import objects, viewproviders
from .gui_actions import active_analysis, analysis_line, error, refs_code, run, selected_faces, status

SETUP = ["ThermoDec_ImportStep", "ThermoDec_OpenModel", "ThermoDec_Analysis", "ThermoDec_NodeFromSelection", "ThermoDec_MaterialToSelection",
         "ThermoDec_AutoNodesPerFace", "ThermoDec_AutoNodesPerSolid", "ThermoDec_Conductance",
         "ThermoDec_Environment"]
RUN = ["ThermoDec_Tessellate", "ThermoDec_Export", "ThermoDec_ExportTool", "ThermoDec_Simulate", "ThermoDec_ShowResult",
       "ThermoDec_Plots", "ThermoDec_Decimate", "ThermoDec_Reduce", "ThermoDec_ImportResults"]


class _Command:
    icon = "ThermoDec.svg"
    menu = ""
    tip = ""

    def GetResources(self):
        return {"Pixmap": viewproviders.icon(self.icon), "MenuText": self.menu, "ToolTip": self.tip}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and active_analysis() is not None


class ImportStep(_Command):
    icon, menu, tip = "ImportStep.svg", "Import STEP", "Load a STEP file as one shape (Part.read)"

    def IsActive(self):
        return True

    def Activated(self):
        from PySide import QtGui
        path, _ = QtGui.QFileDialog.getOpenFileName(FreeCADGui.getMainWindow(), "STEP file", "",
                                                    "STEP (*.step *.stp *.STEP *.STP)")
        if not path:
            return
        if FreeCAD.ActiveDocument is None:
            FreeCAD.newDocument()
        if run("Import STEP", ["tdo.import_step(App.ActiveDocument, %r)" % path]):
            FreeCADGui.SendMsgToActiveView("ViewFit")


class OpenModel(_Command):
    icon, menu, tip = "ImportResults.svg", "Open model file", \
        "Open a thermodec model.json as an analysis over its mesh: nodes, materials, links, environment; " \
        "merged nodes listed with their members; keys the workbench does not edit are kept"

    def IsActive(self):
        return True

    def Activated(self):
        from PySide import QtGui
        path, _ = QtGui.QFileDialog.getOpenFileName(FreeCADGui.getMainWindow(), "thermodec model file", "",
                                                    "thermodec model (*.json)")
        if not path:
            return
        import os
        import re
        # A document of its own: node and material labels are the model's names.
        FreeCAD.newDocument(re.sub(r"\W", "_", os.path.basename(os.path.dirname(path)) or "Model"))
        if run("Open thermodec model", ["import thermodec_freecad.model_file as tdmodel",
                                        "tdmodel.open_model(App.ActiveDocument, %r)" % path]):
            FreeCADGui.SendMsgToActiveView("ViewFit")


class Analysis(_Command):
    icon, menu, tip = "Analysis.svg", "Thermal analysis", "Create a thermal analysis container"

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def Activated(self):
        run("Create thermal analysis", ["tdo.makeAnalysis(App.ActiveDocument)"])


class NodeFromSelection(_Command):
    icon, menu, tip = "Node.svg", "Node from selection", \
        "Make a thermal node from the selected faces or shapes"

    def Activated(self):
        refs = selected_faces()
        if not refs:
            return error("select faces or shapes first")
        from . import taskpanels
        FreeCADGui.Control.showDialog(taskpanels.NodePanel(active_analysis(), refs))


class MaterialToSelection(_Command):
    icon, menu, tip = "Material.svg", "Material to selection", \
        "Give the selected faces (or the selected nodes) a coating from the library"

    def Activated(self):
        from . import taskpanels
        nodes = [o for o in FreeCADGui.Selection.getSelection() if objects.is_type(o, objects.ThermalNode)]
        refs = selected_faces()
        if not nodes and not refs:
            return error("select faces, shapes or thermal nodes first")
        FreeCADGui.Control.showDialog(taskpanels.MaterialPanel(active_analysis(), refs, nodes))


class AutoNodes(_Command):
    per = "face"

    def Activated(self):
        shapes = [o for o, _ in selected_faces()]
        if not shapes:
            return error("select one or more shapes first")
        run("Automatic nodes per " + self.per, [
            analysis_line(),
            "tdo.automatic_nodes(analysis, [%s], per=%r)" % (
                ", ".join("App.ActiveDocument.%s" % o.Name for o in shapes), self.per)])


class AutoNodesPerFace(AutoNodes):
    icon, menu, tip, per = "AutoNodes.svg", "Automatic nodes per face", \
        "One thermal node per B-rep face of the selected shapes", "face"


class AutoNodesPerSolid(AutoNodes):
    icon, menu, tip, per = "AutoNodes.svg", "Automatic nodes per solid", \
        "One thermal node per solid of the selected shapes", "solid"


class ConductanceCommand(_Command):
    icon, menu, tip = "Conductance.svg", "Conductance", "Conductive link between two selected nodes"

    def Activated(self):
        nodes = [o for o in FreeCADGui.Selection.getSelection() if objects.is_type(o, objects.ThermalNode)]
        if len(nodes) != 2:
            return error("select exactly two thermal nodes")
        from PySide import QtGui
        value, ok = QtGui.QInputDialog.getDouble(FreeCADGui.getMainWindow(), "Conductance",
                                                 "GL [W/K]", 1.0, 0.0, 1e6, 4)
        if ok:
            run("Conductance", [analysis_line(), "tdo.makeConductance(analysis, App.ActiveDocument.%s, "
                                "App.ActiveDocument.%s, %r)" % (nodes[0].Name, nodes[1].Name, value)])


class EnvironmentCommand(_Command):
    icon, menu, tip = "Environment.svg", "Environment", "Orbit or fixed-sun environment"

    def Activated(self):
        from . import taskpanels
        analysis = active_analysis()
        envs = objects.members(analysis, objects.Environment)
        FreeCADGui.Control.showDialog(taskpanels.EnvironmentPanel(analysis, envs[0] if envs else None))


class Tessellate(_Command):
    icon, menu, tip = "Tessellate.svg", "Tessellate", \
        "Dense mesh of the analysis' shapes with a max edge length; triangles keep node and material"

    def Activated(self):
        from . import taskpanels
        FreeCADGui.Control.showDialog(taskpanels.TessellatePanel(active_analysis()))


class Export(_Command):
    icon, menu, tip = "Export.svg", "Export model", "Write thermodec model.json and its mesh"

    def Activated(self):
        from PySide import QtGui
        from . import export
        analysis = active_analysis()
        default, _ = export.default_paths(analysis)
        path, _ = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(), "Export thermodec model",
                                                    default, "thermodec model (*.json)")
        if not path:
            return

        def write():
            status("ThermoDec: exporting %s ..." % path)
            if run("Export thermodec model", [
                    "analysis = App.ActiveDocument.%s" % analysis.Name, "import thermodec_freecad.export as tdexport",
                    "tdexport.write_model(analysis, %r)" % path]):
                status("ThermoDec: model written to %s" % path)

        from . import taskpanels
        if not taskpanels._needs_mesh(analysis, write):  # else tessellated in the background first
            write()


class _CoreCommand(_Command):
    function = ""

    def IsActive(self):
        try:
            import thermodec
        except ImportError:
            return False
        return _Command.IsActive(self) and hasattr(thermodec, self.function)


class Simulate(_CoreCommand):
    icon, menu, tip, function = "Simulate.svg", "Simulate", \
        "Export and run the reference thermal simulation (thermodec simulate) in the background", "simulate_model"

    def Activated(self):
        from . import taskpanels
        taskpanels.start_simulate(active_analysis())  # progress and Cancel in a panel; imported when done


class ShowResult(_Command):
    icon, menu, tip = "Result.svg", "Thermal result", \
        "Per-node min / mean / max over the orbit, colour bar, and the field or time step shown"

    def _result(self):
        from . import thermal_result
        selected = [o for o in FreeCADGui.Selection.getSelection() if objects.is_type(o, thermal_result.ThermalResult)]
        if selected:
            return selected[0]
        analysis = active_analysis()
        found = objects.members(analysis, thermal_result.ThermalResult) if analysis is not None else []
        return found[-1] if found else None

    def IsActive(self):
        return _Command.IsActive(self) and self._result() is not None

    def Activated(self):
        result = self._result()
        if result is None:
            return error("simulate first: the analysis has no thermal result")
        FreeCADGui.activeDocument().setEdit(result.Name)


class Decimate(_CoreCommand):
    icon, menu, tip, function = "Decimate.svg", "Decimate", \
        "Node-preserving decimation of the dense mesh to a global ratio (thermodec decimate, in the background)", \
        "decimate_to_global_ratio"

    def Activated(self):
        from PySide import QtGui
        analysis = active_analysis()
        ratio, ok = QtGui.QInputDialog.getDouble(FreeCADGui.getMainWindow(), "Decimate",
                                                 "Fraction of faces to remove", analysis.GlobalRatio,
                                                 0.0, 0.999, 3)
        if ok and run("Decimate settings", [analysis_line(), "analysis.GlobalRatio = %r" % ratio]):
            from . import taskpanels
            taskpanels.start_decimate(analysis)  # in the background, with progress and Cancel


class Reduce(_CoreCommand):
    icon, menu, tip, function = "Reduce.svg", "Reduce", \
        "Simulation-driven reduction to the analysis' temperature tolerance (thermodec core)", \
        "reduce_model"

    def Activated(self):
        from . import taskpanels
        FreeCADGui.Control.showDialog(taskpanels.ReducePanel(active_analysis()))


class ExportTool(_CoreCommand):
    icon, menu, tip, function = "Export.svg", "Export for other tools", \
        "Write the model for other thermal and post-processing tools, in a format of `thermodec export`", \
        "export_model"

    def Activated(self):
        from PySide import QtGui
        from . import results, taskpanels
        window = FreeCADGui.getMainWindow()
        analysis = active_analysis()
        which = "the reduced model (%s)" % analysis.ReducedModelFile if results.reduced_model_current(analysis) \
            else "the dense model (no current reduced model: Reduce first to export it)"
        formats = {f["name"]: f for f in results.exchange_formats()}  # the core's table, in menu order
        fmt, ok = QtGui.QInputDialog.getItem(window, "Export for other tools", "Exports %s\nFormat" % which,
                                             list(formats), 0, False)
        if not ok:
            return
        row = formats[fmt]
        if row["output"] == "folder":
            out = QtGui.QFileDialog.getExistingDirectory(window, "Folder of the %s" % row["title"])
        else:
            out, _ = QtGui.QFileDialog.getSaveFileName(window, "Export as " + fmt, "", results.file_dialog_filter(row))
        if out:
            taskpanels.start_export(analysis, fmt, out)  # in the background, with progress and Cancel


class Plots(_Command):
    icon, menu, tip = "Result.svg", "Thermal plots", \
        "Temperatures over the orbit per node (original vs reduced) and the reduction's sensitivity curves"

    def IsActive(self):
        from . import plots
        analysis = active_analysis() if FreeCAD.ActiveDocument is not None else None
        return analysis is not None and plots._result_on(analysis, "ThermalMesh") is not None

    def Activated(self):
        from . import plots
        try:
            plots.PlotDock(active_analysis())
        except Exception as e:
            error(e)


class ImportResults(_Command):
    icon, menu, tip = "ImportResults.svg", "Import results", \
        "Load a (reduced) mesh coloured by node, or by temperature with a results JSON"

    def Activated(self):
        from PySide import QtGui
        window = FreeCADGui.getMainWindow()
        mesh, _ = QtGui.QFileDialog.getOpenFileName(window, "Reduced mesh", "", "Meshes (*.obj *.ply *.stl)")
        if not mesh:
            return
        temps, _ = QtGui.QFileDialog.getOpenFileName(window, "Temperatures (optional)", "", "JSON (*.json)")
        run("Import results", [analysis_line(), "import thermodec_freecad.results as tdresults",
                               "tdresults.import_results(analysis, %r, %r)" % (mesh, temps or None)])


def register():
    for name, cls in (("ThermoDec_ImportStep", ImportStep), ("ThermoDec_OpenModel", OpenModel), ("ThermoDec_Analysis", Analysis), ("ThermoDec_NodeFromSelection", NodeFromSelection),
                      ("ThermoDec_MaterialToSelection", MaterialToSelection),
                      ("ThermoDec_AutoNodesPerFace", AutoNodesPerFace),
                      ("ThermoDec_AutoNodesPerSolid", AutoNodesPerSolid),
                      ("ThermoDec_Conductance", ConductanceCommand),
                      ("ThermoDec_Environment", EnvironmentCommand),
                      ("ThermoDec_Tessellate", Tessellate), ("ThermoDec_Export", Export),
                      ("ThermoDec_ExportTool", ExportTool),
                      ("ThermoDec_Simulate", Simulate), ("ThermoDec_ShowResult", ShowResult),
                      ("ThermoDec_Plots", Plots),
                      ("ThermoDec_Decimate", Decimate),
                      ("ThermoDec_Reduce", Reduce),
                      ("ThermoDec_ImportResults", ImportResults)):
        FreeCADGui.addCommand(name, cls())
