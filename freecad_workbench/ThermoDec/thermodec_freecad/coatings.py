"""Thermo-optical properties of common spacecraft coatings (beginning of life).

Values are solar absorptivity alpha_s and IR hemispherical emissivity eps at beginning of
life, typical values for preliminary design only: real values depend on the product,
thickness and ageing (alpha of white paint and OSR grows in orbit), so use the product
datasheet when you have it. Each entry's source string names the table the numbers were
checked against. Sources:
  [Fortescue] P. Fortescue, G. Swinerd, J. Stark (eds), Spacecraft Systems Engineering,
              4th ed., Wiley, 2011, Table 11.3 (alpha and eps of surfaces and finishes);
              public copy: https://www.mouflon.goats.se/external_files_chalmers/yr6/RRY016%20Space%20Engineering/a%20and%20e%20for%20various%20surfaces%20and%20finishes_files/sheet001.htm
  [Gilmore]   D. G. Gilmore (ed.), Spacecraft Thermal Control Handbook, Vol. I, 2nd ed.,
              The Aerospace Press, 2002, Appendix A (values courtesy NASA/GSFC); OSR rows
              checked at https://www.globalspec.com/reference/39518/203279/appendix-a-surface-optical-property-data
Not consulted: L. Kauder, Spacecraft Thermal Control Coatings References, NASA/TP-2005-212792
(https://ntrs.nasa.gov/citations/20070014757) - its tables were not reachable when these
values were checked, so product-specific values (S13G-LO, Z-93, Aeroglaze Z306) are unverified.
"""

#: name -> (absorptivity, emissivity, source)
COATINGS = {
    "white_paint": (0.20, 0.85, "[Gilmore] App. A, white paint (S13G-LO / Z-93 class), BOL - unverified; "
                                "bracketed by [Fortescue] Table 11.3 white paint silicone a 0.26 e 0.83, "
                                "silicate a 0.12 e 0.90"),
    "black_paint": (0.95, 0.87, "[Fortescue] Table 11.3, black paint (polyurethane): a 0.95, e 0.90 "
                                "(e.g. Aeroglaze Z306; Z306-specific values unverified)"),
    "mli_outer_layer": (0.40, 0.63, "[Fortescue] Table 11.3, aluminised Kapton, Kapton outside: a 0.40, e 0.63 "
                                    "(thickness not stated; 1 mil assumed)"),
    "osr": (0.08, 0.80, "[Gilmore] App. A (NASA/GSFC data, via GlobalSpec), OSR silvered fused silica: "
                        "a 0.07, e 0.80"),
    "solar_cell": (0.75, 0.82, "[Fortescue] Table 11.3, solar cells, silicon (typical values): a 0.75, e 0.82"),
    "bare_aluminium": (0.24, 0.08, "[Fortescue] Table 11.3, polished aluminium: a 0.24, e 0.08 "
                                   "(alloy not stated; used for 6061-T6)"),
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
