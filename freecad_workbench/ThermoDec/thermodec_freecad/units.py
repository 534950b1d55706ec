"""The one place where FreeCAD's units become thermodec's SI units.

FreeCAD stores lengths in mm and angles in degrees; thermodec works in m, K, W, J/K, W/K,
W/m^2. Thermal properties of the workbench objects are already SI floats (their tooltips
say the unit), so only geometry, lengths and angles convert here."""


MM_TO_M = 1e-3


def length_m(value):
    """A FreeCAD length (Quantity, property value or float in mm) in metres."""
    if hasattr(value, "getValueAs"):
        return float(value.getValueAs("m"))
    return float(value) * MM_TO_M


def area_m2(value_mm2):
    """A FreeCAD area (Part face Area, in mm^2) in m^2."""
    if hasattr(value_mm2, "getValueAs"):
        return float(value_mm2.getValueAs("m^2"))
    return float(value_mm2) * MM_TO_M * MM_TO_M


def length_km(value):
    return length_m(value) * 1e-3


def angle_deg(value):
    if hasattr(value, "getValueAs"):
        return float(value.getValueAs("deg"))
    return float(value)


def points_m(points_mm):
    """#V x 3 numpy array of positions in mm -> m."""
    return points_mm * MM_TO_M


def points_mm(points_m):
    """#V x 3 numpy array of positions in m -> mm (results back into FreeCAD)."""
    return points_m / MM_TO_M
