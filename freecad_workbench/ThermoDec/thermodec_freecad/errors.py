"""The workbench's one exception type (headless: raised with the message; GUI: shown in a dialog)."""


class ThermoDecError(Exception):
    """Bad or incomplete thermal set-up; the message names the object or face and says why."""
