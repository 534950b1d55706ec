# ThermoDec workbench, GUI part (FreeCAD executes this file; it is not imported as a module).


class ThermoDecWorkbench(Workbench):  # noqa: F821 (Workbench is provided by FreeCAD)
    MenuText = "ThermoDec"
    ToolTip = "Thermal nodes and coatings on CAD; tessellate, export and reduce with thermodec"

    def __init__(self):
        import os
        import thermodec_freecad
        self.__class__.Icon = os.path.join(os.path.dirname(thermodec_freecad.__file__), os.pardir,
                                           "Resources", "icons", "ThermoDec.svg")

    def Initialize(self):
        from thermodec_freecad import commands
        commands.register()
        self.appendToolbar("ThermoDec setup", commands.SETUP)
        self.appendToolbar("ThermoDec run", commands.RUN)
        self.appendMenu("ThermoDec", commands.SETUP + ["Separator"] + commands.RUN)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(ThermoDecWorkbench())  # noqa: F821
