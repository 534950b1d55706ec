"""Physical defaults of automatic nodes: a default structural panel (docs/freecad.md,
"Automatic nodes").

Every B-rep face is taken as one aluminium honeycomb sandwich panel, the usual spacecraft
structure: two 0.3 mm Al 7075-T6 face sheets over a 25 mm Al 5056 honeycomb core of
49.7 kg/m^3 (3.1 lb/ft^3, a common aerospace core density). Material data are ASM / MatWeb
handbook values (7075-T6: 2810 kg/m^3, 960 J/(kg K), 130 W/(m K); 5056: 904 J/(kg K)).
Adhesive, inserts and equipment are left out: the default stores less heat than a real panel,
so temperature swings come out larger, not smaller. No FreeCAD import here: plain numbers.
"""

#: (name, thickness [m], density [kg/m^3], specific heat [J/(kg K)], in-plane conductivity [W/(m K)])
PANEL_LAYERS = (
    ("face sheets, 2 x 0.3 mm Al 7075-T6", 2 * 0.3e-3, 2810.0, 960.0, 130.0),
    ("core, 25 mm Al 5056 honeycomb 49.7 kg/m^3", 25e-3, 49.7, 904.0, 0.0),  # foil: no in-plane path counted
)

PANEL_NAME = "aluminium honeycomb panel (2 x 0.3 mm Al 7075 sheets, 25 mm Al 5056 core)"


def areal_heat_capacity_J_per_m2K(layers=PANEL_LAYERS):
    """Heat capacity per unit area of the panel: sum of thickness x density x specific heat
    [J/(m^2 K)] (2742 J/(m^2 K) for the default panel)."""
    return sum(t * rho * cp for _, t, rho, cp, _ in layers)


def sheet_conductance_W_per_K(layers=PANEL_LAYERS):
    """In-plane conductance of a square of the panel, sum of conductivity x thickness [W/K]
    (0.078 W/K for the default panel: the face sheets)."""
    return sum(t * k for _, t, _, _, k in layers)


def face_capacitance_J_per_K(area_m2, areal_J_per_m2K):
    """Heat capacity [J/K] of a face of `area_m2` [m^2] taken as one panel."""
    return area_m2 * areal_J_per_m2K


def edge_conductance_W_per_K(sheet_W_per_K, edge_length_m, distance_a_m, distance_b_m):
    """Conductance [W/K] between two faces across their shared edge of length L [m]: the panel
    continues over the edge, each face conducting from its centroid (at distance d_a, d_b [m]
    from the edge) to the edge in series, G = k t L / (d_a + d_b). 0.078 W/K between two faces
    of a 1 m box. A bolted corner conducts less; set the link's value when it is known."""
    path = distance_a_m + distance_b_m
    if path <= 0 or edge_length_m <= 0:
        return 0.0
    return sheet_W_per_K * edge_length_m / path
