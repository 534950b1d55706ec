"""Thermo-optical properties of common spacecraft coatings (beginning of life).

Values are solar absorptivity alpha_s and IR hemispherical emissivity eps at beginning of
life, typical values within the ranges tabulated in the sources below, for preliminary
design only: real values depend on the product, thickness and ageing (alpha of white paint
and OSR grows in orbit), so use the product datasheet when you have it. Sources:
  [Gilmore]  D. G. Gilmore (ed.), Spacecraft Thermal Control Handbook, Vol. I, 2nd ed.,
             The Aerospace Press, 2002, Appendix A (optical properties tables).
  [Karam]    R. D. Karam, Satellite Thermal Control for Systems Engineers, AIAA, 1998,
             Table 4.3.
"""

#: name -> (absorptivity, emissivity, source)
COATINGS = {
    "white_paint": (0.20, 0.85, "[Gilmore] App. A, white paint (e.g. S13G-LO / Z-93 class), BOL"),
    "black_paint": (0.95, 0.87, "[Gilmore] App. A, black paint (e.g. Aeroglaze Z306)"),
    "mli_outer_layer": (0.40, 0.76, "[Gilmore] App. A, aluminised Kapton outer layer, 1 mil, Kapton side out"),
    "osr": (0.08, 0.80, "[Gilmore] App. A, optical solar reflector, silvered fused silica"),
    "solar_cell": (0.82, 0.85, "[Karam] Table 4.3, silicon solar cell with cover glass"),
    "bare_aluminium": (0.15, 0.05, "[Gilmore] App. A, polished aluminium 6061-T6"),
}


def coating_names():
    return sorted(COATINGS)


def coating(name):
    """(absorptivity, emissivity, source) of a library coating; KeyError lists the known ones."""
    try:
        return COATINGS[name]
    except KeyError:
        raise KeyError("unknown coating '%s' (known: %s)" % (name, ", ".join(coating_names()))) from None


def read_fcmat(path):
    """(absorptivity, emissivity) from a FreeCAD .FCMat card (INI style).

    Reads the keys SolarAbsorptivity/Absorptivity and Emissivity in any section.
    Raises ValueError naming the file when a key is missing or not a number."""
    import configparser
    parser = configparser.ConfigParser(strict=False, interpolation=None)
    parser.optionxform = str
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if not text.lstrip().startswith("["):
        text = "[General]\n" + text
    parser.read_string(text, source=path)
    values = {}
    for section in parser.sections():
        for key, value in parser.items(section):
            values[key] = value
    out = []
    for keys in (("SolarAbsorptivity", "Absorptivity"), ("Emissivity",)):
        found = [values[k] for k in keys if k in values]
        if not found:
            raise ValueError("%s: material card has no %s key" % (path, " or ".join(keys)))
        try:
            out.append(float(found[0].split()[0]))
        except ValueError:
            raise ValueError("%s: %s = '%s' is not a number" % (path, keys[0], found[0])) from None
    return tuple(out)
