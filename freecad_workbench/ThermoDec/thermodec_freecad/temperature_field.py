"""What a thermal result shows, as plain numbers (no FreeCAD import): per-node statistics over
the orbit, the field chosen for display (min, mean, max or one time step) per triangle, and the
colour map with its legend. The ThermalResult object and its task panel build on these."""

import colorsys

import numpy as np

from .errors import ThermoDecError

#: Statistics over the orbit a result can show; any other field is a time step index.
STATISTICS = ("mean", "min", "max")

#: Colour levels of the map: the mesh shows at most this many colours, the legend the same.
LEVELS = 32


def temperature_matrix(result):
    """(node names, times [s] #S, temperatures [K] #N x #S) of a result.json dict (what
    `thermodec simulate` and Simulate write). Raises ThermoDecError when it is not one."""
    try:
        nodes = [str(n) for n in result["nodes"]]
        times = np.asarray(result["times_s"], dtype=float).reshape(-1)
        rows = [np.asarray(result["temperatures_K"][n], dtype=float).reshape(-1) for n in nodes]
    except (KeyError, TypeError, ValueError) as e:
        raise ThermoDecError("not a thermodec result (nodes, times_s, temperatures_K): %s" % e) from None
    if not nodes or len(times) == 0:
        raise ThermoDecError("the result has no node or no time")
    for name, row in zip(nodes, rows):
        if len(row) != len(times):
            raise ThermoDecError("node '%s' has %d temperatures for %d times" % (name, len(row), len(times)))
    T = np.vstack(rows)
    if not np.all(np.isfinite(T)) or np.any(T <= 0):
        raise ThermoDecError("the result holds temperatures that are not positive kelvin")
    return nodes, times, T


def node_statistics(T):
    """Per node over the orbit: (min, mean, max) [K], each #N, of temperatures #N x #S [K].
    The mean is the time average over the result's samples (equally spaced over one orbit)."""
    T = np.asarray(T, dtype=float)
    if T.ndim != 2 or T.shape[1] == 0:
        raise ThermoDecError("temperatures must be nodes x times with at least one time")
    return T.min(axis=1), T.mean(axis=1), T.max(axis=1)


def field_name(field, times=None):
    """Label of a field: 'mean' / 'min' / 'max' over the orbit, or 'step k (t = ... s)'."""
    if field in STATISTICS:
        return "%s over the orbit" % field
    k = int(field)
    if times is not None and 0 <= k < len(times):
        return "step %d (t = %.0f s)" % (k, times[k])
    return "step %d" % k


def node_field(T, field):
    """Per-node temperature [K] of `field`: one of STATISTICS, or a time step index."""
    T = np.asarray(T, dtype=float)
    if field in STATISTICS:
        low, mean, high = node_statistics(T)
        return {"min": low, "mean": mean, "max": high}[field]
    try:
        k = int(field)
    except (TypeError, ValueError):
        raise ThermoDecError("field must be min, mean, max or a time step, not %r" % (field,)) from None
    if not 0 <= k < T.shape[1]:
        raise ThermoDecError("time step %d outside 0..%d" % (k, T.shape[1] - 1))
    return T[:, k]


def face_values(node_values, face_node, mesh_node_names, result_nodes):
    """Per-triangle values [K]: each triangle takes its node's value. The mesh's nodes are
    matched to the result's by name (a mesh may list its nodes in another order)."""
    index = {name: i for i, name in enumerate(result_nodes)}
    missing = [n for n in mesh_node_names if n not in index]
    if missing:
        raise ThermoDecError("no temperature for node(s) %s" % ", ".join(missing[:8]))
    to_result = np.array([index[n] for n in mesh_node_names], dtype=int)
    return np.asarray(node_values, dtype=float)[to_result[np.asarray(face_node, dtype=int)]]


def heat_colour(x):
    """Colour (r, g, b in 0..1) of x in [0, 1]: blue (cold) - cyan - green - yellow - red (hot)."""
    x = min(max(float(x), 0.0), 1.0)
    return colorsys.hsv_to_rgb((1.0 - x) * 2.0 / 3.0, 0.9, 0.95)


def colour_range(values):
    """(low, high) [K] of the colour map: the values' range, widened to 1 K when flat (steady
    state of an isothermal model) so that the map stays defined."""
    low, high = float(np.min(values)), float(np.max(values))
    if high - low < 1e-9:
        return low - 0.5, high + 0.5
    return low, high


def colours(values, low, high, levels=LEVELS):
    """One colour per value: the map quantised to `levels` steps between low and high [K]
    (values outside are clamped), so the mesh shows the legend's colours and no others."""
    x = (np.asarray(values, dtype=float) - low) / (high - low)
    steps = np.round(np.clip(x, 0.0, 1.0) * (levels - 1)) / (levels - 1)
    return [heat_colour(s) for s in steps]


def legend(low, high, ticks=5, levels=LEVELS):
    """The colour bar: ([(value [K], colour)] of its `levels` bands, bottom to top, and
    [(value [K], label)] of `ticks` evenly spaced labels from low to high)."""
    bands = [(low + (high - low) * k / (levels - 1), heat_colour(k / (levels - 1))) for k in range(levels)]
    labels = [(low + (high - low) * k / (ticks - 1), "%.1f K" % (low + (high - low) * k / (ticks - 1)))
              for k in range(ticks)]
    return bands, labels


def statistics_table(nodes, T):
    """Rows (node, min, mean, max [K]) of the task panel's table, hottest mean first."""
    low, mean, high = node_statistics(T)
    rows = [(n, float(a), float(b), float(c)) for n, a, b, c in zip(nodes, low, mean, high)]
    return sorted(rows, key=lambda r: -r[2])
