"""Results back into FreeCAD: a (reduced) mesh read by the core, as a Mesh feature coloured by
node or by temperature, and a short report. simulate/reduce run the core through the binding
once this build of the core has them."""

import json
import os
import threading

import numpy as np

import FreeCAD

from . import core, export, merged_nodes, objects, temperature_field, tessellate, thermal_result, units
from .errors import ThermoDecError
from .files import atomic_write_text


def _node_temperatures(temperatures):
    """{node name: K} from a dict or a JSON file holding one (optionally under 'temperatures_K')."""
    if temperatures is None:
        return None
    if isinstance(temperatures, str):
        try:
            with open(temperatures, encoding="utf-8") as f:
                temperatures = json.load(f)
        except (OSError, ValueError) as e:
            raise ThermoDecError("cannot read temperatures from %s: %s" % (temperatures, e)) from None
    if "temperatures_K" in temperatures:
        temperatures = temperatures["temperatures_K"]
    try:
        return {str(k): float(v) for k, v in temperatures.items()}
    except (TypeError, ValueError, AttributeError):
        raise ThermoDecError("temperatures must map node names to kelvin") from None


def _is_result(data):
    """True for a result.json dict (time series per node), not a {node: K} map."""
    return isinstance(data, dict) and "times_s" in data and "nodes" in data


def import_results(analysis, mesh_path, temperatures=None, name="Results"):
    """Reads `mesh_path` with the core and adds it to the analysis as a Mesh feature with
    per-triangle node. `temperatures`: a {node name: K} map (or a JSON file holding one,
    optionally under 'temperatures_K') colours the triangles; a result.json (`thermodec
    simulate`, Simulate) adds a ThermalResult with its time series (colour bar, min/mean/max,
    time steps). Returns (feature, summary dict)."""
    td = core.module()
    source = temperatures if isinstance(temperatures, str) else ""
    if source:
        temperatures = _read_json(source)
    if _is_result(temperatures):
        nodes, times, T = temperature_field.temperature_matrix(temperatures)
        feature, summary = _mesh_feature(analysis, td.read_mesh(mesh_path), mesh_path, None, name)
        res = thermal_result.makeResult(analysis, feature, nodes, times, T, result_file=source)
        summary.update(temperature_min_K=res.ColourMinK, temperature_max_K=res.ColourMaxK, result=res.Name)
        return feature, summary
    return _mesh_feature(analysis, td.read_mesh(mesh_path), mesh_path, temperatures, name)


def _read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise ThermoDecError("cannot read temperatures from %s: %s" % (path, e)) from None


def _mesh_feature(analysis, mesh, mesh_path, temperatures, name):
    """A core mesh as a ThermalMesh feature of the analysis (mm), by node or by temperature."""
    import Mesh
    face_node = np.asarray(mesh.face_node)
    if np.any(face_node < 0):
        raise ThermoDecError("%s: %d triangles have no node" % (mesh_path, int(np.sum(face_node < 0))))
    node_names = list(mesh.node_names)
    V = units.points_mm(np.asarray(mesh.V))
    F = np.asarray(mesh.F)
    feature = analysis.Document.addObject("Mesh::FeaturePython", name)
    tessellate.ThermalMesh(feature)
    if FreeCAD.GuiUp:
        from . import viewproviders
        viewproviders.ViewProviderThermalMesh(feature.ViewObject)
        feature.ViewObject.Lighting = "Two side"  # thin sheets (wings) are seen from both sides
    analysis.addObject(feature)
    # One point triple per triangle: the (points, indices) form drops triangles whose edge
    # another two already share (a wing hinge, an instrument foot), and FaceNode would then
    # no longer line up with the facets.
    points = [FreeCAD.Vector(*p) for p in V]
    feature.Mesh = Mesh.Mesh([[points[int(j)] for j in t] for t in F])
    if feature.Mesh.CountFacets != len(F):
        raise ThermoDecError("%s: FreeCAD kept %d of %d triangles" % (mesh_path, feature.Mesh.CountFacets, len(F)))
    feature.FaceNode = [int(n) for n in face_node]
    feature.FaceMaterial = [int(m) for m in np.asarray(mesh.face_material)]
    feature.NodeNames = node_names
    feature.MaterialNames = list(mesh.material_names)
    summary = {"mesh": mesh_path, "faces": int(len(F)), "vertices": int(len(V)), "nodes": len(node_names)}

    node_t = _node_temperatures(temperatures)
    if node_t is not None:
        missing = [n for n in node_names if n not in node_t]
        if missing:
            raise ThermoDecError("no temperature for node(s) %s" % ", ".join(missing[:8]))
        face_t = [node_t[node_names[n]] for n in face_node]
        feature.FaceTemperature = face_t
        summary.update(temperature_min_K=min(face_t), temperature_max_K=max(face_t))
    if FreeCAD.GuiUp:
        from . import viewproviders
        if node_t is not None:
            viewproviders.colour_by_temperature(feature, feature.FaceTemperature,
                                                summary["temperature_min_K"], summary["temperature_max_K"])
        else:
            viewproviders.colour_by_node(feature)
    FreeCAD.Console.PrintMessage("ThermoDec results: %s\n" % json.dumps(summary))
    return feature, summary


def _remove_mesh(analysis, name):
    """Removes the mesh feature `name` (an earlier run's) and the results shown on it."""
    old = analysis.Document.getObject(name)
    if old is None:
        return
    for res in objects.members(analysis, thermal_result.ThermalResult):
        if res.ResultMesh == old:
            analysis.Document.removeObject(res.Name)
    merged_nodes.clear(old)
    analysis.Document.removeObject(old.Name)


def _result_of(analysis, mesh, result, model, result_path, name="ThermalResult"):
    """The ThermalResult of a core SimulationResult on `mesh`, with the model's seed and rays
    per face: what the simulation used (simulate_model reads them from model.radiation)."""
    return thermal_result.makeResult(analysis, mesh, list(result.nodes), np.asarray(result.times_s),
                                     np.asarray(result.temperature_K), seed=model.radiation.seed,
                                     rays_per_face=model.radiation.rays_per_face, result_file=result_path,
                                     name=name)


def simulate_model_file(analysis, model_path, name="SimulatedMesh"):
    """Simulates a thermodec model file as it is (e.g. sample_models/satellite/model.json:
    what `thermodec simulate` runs), writes <model stem>_result.json into the analysis'
    output folder and adds the model's mesh with a ThermalResult to the analysis.
    Returns (mesh feature, ThermalResult)."""
    td = core.module()
    core.require("simulate_model")
    _progress("simulating %s" % model_path)
    model = td.load_model(model_path)
    result = td.simulate_model(model, _progress)
    folder = os.path.dirname(export.default_paths(analysis)[0])
    os.makedirs(folder, exist_ok=True)
    stem = os.path.splitext(os.path.basename(model_path))[0]
    result_path = os.path.join(folder, "%s_result.json" % stem)
    _write_json(result_path, result.to_json())
    _remove_mesh(analysis, name)
    feature, _ = _mesh_feature(analysis, model.mesh, model_path, None, name)
    merged_nodes.show_from_model_file(analysis, feature, model_path)
    res = _result_of(analysis, feature, result, model, result_path, name + "Result")
    _progress("simulation done: %s (%s %.1f K .. %.1f K)" % (result_path, res.Shown, res.ColourMinK, res.ColourMaxK))
    return feature, res


def _progress(message):
    FreeCAD.Console.PrintMessage("ThermoDec: %s\n" % message)
    if FreeCAD.GuiUp:
        import FreeCADGui
        from PySide import QtGui
        FreeCADGui.getMainWindow().statusBar().showMessage("ThermoDec: %s" % message)
        QtGui.QApplication.processEvents()


def _write_json(path, data):
    atomic_write_text(path, json.dumps(data, indent=1) + "\n")


def node_summary(result_json):
    """{node: {"min_K", "mean_K", "max_K", "noise_K"?}} of a result file's summary, without the
    result-wide entries beside them (time_error_K, orbit_sampling_error_K)."""
    return {name: entry for name, entry in result_json["summary"].items() if isinstance(entry, dict)}


def simulate(analysis, json_path=None):
    """Exports the analysis, runs the core's reference simulation (thermodec.simulate_model,
    what `thermodec simulate` runs) and writes result.json beside the model. A ThermalResult
    (thermal_result.py) keeps the node temperatures over the orbit and shows each triangle's
    node mean temperature [K] on the ThermalMesh (colour bar in the GUI).
    Returns (result path, {node: {"min_K", "mean_K", "max_K"}})."""
    td = core.module()
    core.require("simulate_model")
    json_path, _ = export.write_model(analysis, json_path or export.default_paths(analysis)[0])
    _progress("simulating %s" % json_path)
    model = td.load_model(json_path)
    result = td.simulate_model(model, _progress)
    data = result.to_json()
    result_path = os.path.join(os.path.dirname(json_path), "result.json")
    _write_json(result_path, data)
    analysis.ResultFile = result_path
    summary = _noise_message(data, result_path)
    res = _result_of(analysis, analysis.ThermalMesh, result, model, result_path)
    res.TracksAnalysis = True
    _progress("simulation done: %s (%s %.1f K .. %.1f K)" % (result_path, res.Shown, res.ColourMinK, res.ColourMaxK))
    return result_path, summary


def _noise_message(data, result_path):
    """Says the result's largest sampling noise in the report view. Returns node_summary(data)."""
    summary = node_summary(data)
    noisiest = max(summary.items(), key=lambda kv: kv[1].get("noise_K", 0.0), default=None)
    if noisiest is not None and "noise_K" in noisiest[1]:
        FreeCAD.Console.PrintMessage(
            "ThermoDec: sampling noise (1 sigma, worst over the orbit): at most %.4f K (node %s); "
            "orbit sampling error %.3g K; per node in %s (summary.<node>.noise_K)\n"
            % (noisiest[1]["noise_K"], noisiest[0], data["summary"].get("orbit_sampling_error_K", 0.0),
               result_path))
    return summary


def import_simulation(analysis, outputs):
    """After a Simulate job (runner.simulate_job, run by the CLI): the result on the analysis'
    ThermalMesh as simulate() makes it. Returns (result path, {node: {"min_K", "mean_K", "max_K"}})."""
    path = outputs["result"]
    analysis.ResultFile = path
    summary = _noise_message(_read_json(path), path)
    res = _result_file(analysis, analysis.ThermalMesh, path, outputs["model"], "ThermalResult")
    _progress("simulation done: %s (%s %.1f K .. %.1f K)" % (path, res.Shown, res.ColourMinK, res.ColourMaxK))
    return path, summary


def exchange_formats():
    """The core's export formats in menu order (thermodec.export_formats(): dicts with name,
    title, extensions, output 'file'/'folder'/'prefix', needs_simulation, help), the same table
    `thermodec export --format` offers."""
    return core.require("export_formats")()


def file_dialog_filter(fmt):
    """The file-dialog filter of a format row: 'ESATAN-TMS network (*.d)'."""
    return "%s (%s)" % (fmt["title"], " ".join("*" + e for e in fmt["extensions"]))


def dense_result_current(analysis):
    """The result.json of the analysis' current (not stale) simulation on its ThermalMesh, or ''."""
    path = analysis.ResultFile
    if not path or not os.path.exists(path) or analysis.ThermalMesh is None:
        return ""
    dense = [r for r in objects.members(analysis, thermal_result.ThermalResult) if r.ResultMesh == analysis.ThermalMesh]
    return path if dense and not dense[-1].Stale and dense[-1].ResultFile == path else ""


def reduced_model_current(analysis):
    """True when the analysis has a reduced model whose result is not stale (Reduce ran since
    the last change of its inputs)."""
    path = analysis.ReducedModelFile
    if not path or not os.path.exists(path):
        return False
    reduced = [r for r in objects.members(analysis, thermal_result.ThermalResult)
               if r.ResultMesh is not None and r.ResultMesh.Name == "ReducedMesh"]
    return bool(reduced) and not reduced[-1].Stale


def model_for_tools(analysis):
    """The model Export for other tools writes: the reduced model.json when current, else the
    dense model, exported now."""
    if reduced_model_current(analysis):
        return analysis.ReducedModelFile
    return export.write_model(analysis, export.default_paths(analysis)[0])[0]


def export_for_tool(analysis, fmt, out, model_path=None):
    """Writes the analysis for another tool (docs/exchange.md) in the format named `fmt`, a name
    of exchange_formats() (out = a file, a folder or a prefix as the row's 'output' says): the reduced
    model when Reduce made a current one, else the dense model (model_for_tools). The network
    formats run the reference simulation first. Returns the files written."""
    td = core.module()
    core.require("export_model")
    json_path = model_path or model_for_tools(analysis)
    _progress("exporting %s as %s" % (json_path, fmt))
    model = td.load_model(json_path)
    files = [str(f) for f in td.export_model(model, fmt, out, "model", _progress)]
    _progress("written: %s" % ", ".join(files))
    return files


def node_mean_temperatures(result_path):
    """{node: mean temperature [K]} of a result.json written by simulate()."""
    with open(result_path, encoding="utf-8") as f:
        return {name: v["mean_K"] for name, v in node_summary(json.load(f)).items()}


def decimate(analysis, global_ratio=None, json_path=None):
    """Exports the analysis and decimates its mesh with the core's node-preserving decimation
    to a global ratio of removed faces (the paper's per-node rule), here (the Decimate command
    runs `thermodec decimate` in the background instead: runner.decimate_job). Writes
    reduced/model.json and reduced/model.obj beside the export and imports the reduced mesh
    (import_decimation). Returns (feature, summary)."""
    td = core.module()
    ratio = analysis.GlobalRatio if global_ratio is None else float(global_ratio)
    json_path, _ = export.write_model(analysis, json_path or export.default_paths(analysis)[0])
    _progress("decimating %s (remove %.0f %% of the faces)" % (json_path, 100 * ratio))
    model = td.load_model(json_path)
    result = td.decimate_to_global_ratio(model.mesh, ratio)
    folder = os.path.join(os.path.dirname(json_path), "reduced")
    os.makedirs(folder, exist_ok=True)
    mesh_path = os.path.join(folder, "model.obj")
    td.write_mesh(mesh_path, result.mesh)
    with open(json_path, encoding="utf-8") as f:
        data = json.load(f)
    data["mesh"] = "model.obj"
    _write_json(os.path.join(folder, "model.json"), data)
    feature, summary = import_decimation(analysis, {"mesh": mesh_path, "global_ratio": ratio})
    summary.update(nodes_reached=sum(1 for n in result.nodes if n.reached))
    return feature, summary


def import_decimation(analysis, outputs):
    """The decimated mesh (outputs: "mesh", the OBJ; "global_ratio") as *ReducedMesh*, coloured
    by the dense model's simulation node by node when there is one (else by the last result
    file's node mean temperatures, else by node). Returns (feature, summary)."""
    dense = [r for r in objects.members(analysis, thermal_result.ThermalResult) if r.ResultMesh == analysis.ThermalMesh]
    temperatures = None
    if not dense and analysis.ResultFile and os.path.exists(analysis.ResultFile):
        temperatures = node_mean_temperatures(analysis.ResultFile)
    _remove_mesh(analysis, "ReducedMesh")
    feature, summary = import_results(analysis, outputs["mesh"], temperatures, name="ReducedMesh")
    if dense:  # the dense model's simulation, node by node, on the reduced triangles
        nodes, times, T = thermal_result.matrix(dense[-1])
        thermal_result.makeResult(analysis, feature, nodes, times, T, seed=dense[-1].Seed, rays_per_face=dense[-1].RaysPerFace,
                                  result_file=dense[-1].ResultFile, name="ReducedMeshResult").TracksAnalysis = True
    summary.update(faces_before=int(analysis.ThermalMesh.Mesh.CountFacets), global_ratio=outputs["global_ratio"])
    _progress("reduced to %d faces (from %d)" % (summary["faces"], summary["faces_before"]))
    return feature, summary


def reduce(analysis, tolerance_K=None, json_path=None, plots=True, cases=()):
    """Simulation-driven reduction through the core (thermodec.reduce_model, what
    `thermodec reduce` runs): exports the analysis, reduces its mesh as far as the temperature
    tolerance [K] allows (verified by a full recompute), writes the core's outputs (model.json +
    reduced.obj, report.json, plots) into reduced/ beside the export and imports the reduced
    mesh coloured by its own simulated node temperatures. Returns (feature, summary).
    `cases`: load case files (`thermodec reduce --case`, docs/model-format.md) the reduced model
    must also meet, e.g. a cold case; they are read (and checked) before any simulation.
    With the analysis' MergeNodes, nodes are merged as well (thermodec.reduce_with_node_merging,
    `reduce --merge-nodes`) and the merged nodes listed under ReducedMesh."""
    td = core.module()
    core.require("reduce_model")
    json_path, mesh_path = export.write_model(analysis, json_path or export.default_paths(analysis)[0])
    settings = td.ReduceSettings()
    settings.tolerance_K = analysis.ToleranceK if tolerance_K is None else float(tolerance_K)
    settings.strategy = getattr(td.ReductionStrategy, analysis.ReductionStrategy)
    main = threading.main_thread()

    def progress(line):  # the core may call from worker threads: only the main thread talks
        if threading.current_thread() is main:
            _progress(line)

    settings.progress = progress
    _progress("reducing %s (tolerance %.3g K, %s)" % (json_path, settings.tolerance_K,
                                                      analysis.ReductionStrategy))
    model = td.load_model(json_path)
    td.apply_large_model_sweep(model, settings)  # as `thermodec reduce` does for this model
    settings.extra_cases = [td.load_case(path, model) for path in cases]
    if getattr(analysis, "MergeNodes", False):  # as `thermodec reduce --merge-nodes`
        run = core.require("reduce_with_node_merging")(model, settings)
    else:
        run = td.reduce_model(model, settings)
    folder = os.path.join(os.path.dirname(json_path), "reduced")
    for warning in td.write_reduction_outputs(run, folder, [json_path, mesh_path], plots):
        FreeCAD.Console.PrintWarning("ThermoDec: %s\n" % warning)
    _remove_mesh(analysis, "ReducedMesh")
    feature, summary = import_results(analysis, os.path.join(folder, "reduced.obj"), None, name="ReducedMesh")
    merged_nodes.show_from_model_file(analysis, feature, os.path.join(folder, "model.json"))
    # The verified reduced model's own simulation, with the seed and rays it ran with.
    _result_of(analysis, feature, run.reduced_result, run.reduced_model, "", name="ReducedMeshResult").TracksAnalysis = True
    summary.update(faces_before=run.faces_before, tolerance_K=run.tolerance_K,
                   noise_floor_K=run.noise_floor_K,
                   max_temperature_difference_K=run.max_temperature_difference_K,
                   max_difference_node=run.max_difference_node, trials=run.trials,
                   cases={c.name: c.max_temperature_difference_K for c in run.cases},
                   seconds=run.seconds_total, report=os.path.join(folder, "report.json"))
    analysis.ReducedModelFile = os.path.join(folder, "model.json")
    FreeCAD.Console.PrintMessage(td.reduction_summary(run) + "\n")
    _progress("reduced %d -> %d faces, max |dT| %.3g K (tolerance %.3g K)" % (
        run.faces_before, run.faces_after, run.max_temperature_difference_K, run.tolerance_K))
    return feature, summary


def _result_file(analysis, mesh, result_path, model_path, name):
    """A ThermalResult on `mesh` from a result.json written by `thermodec simulate --json`,
    with the seed and rays per face of the model file it simulated."""
    data = _read_json(result_path)
    nodes, times, T = temperature_field.temperature_matrix(data)
    radiation = _read_json(model_path).get("radiation", {})
    res = thermal_result.makeResult(analysis, mesh, nodes, times, T, seed=radiation.get("seed"),
                                    rays_per_face=radiation.get("rays_per_face"), result_file=result_path, name=name)
    res.TracksAnalysis = True
    return res


def import_reduction(analysis, outputs, summary=""):
    """After a Reduce job (runner.reduce_job, run by the CLI): the dense result on the
    ThermalMesh (when the job simulated it), the reduced mesh as *ReducedMesh* with the reduced
    model's own simulation, ReducedModelFile set, the CLI's summary in the report view.
    Returns (feature, summary dict from report.json)."""
    td = core.module()
    if outputs.get("simulate_dense", True) and os.path.exists(outputs["result"]):
        analysis.ResultFile = outputs["result"]
        _result_file(analysis, analysis.ThermalMesh, outputs["result"], outputs["model"], "ThermalResult")
    folder = outputs["folder"]
    mesh_path = os.path.join(folder, "reduced.obj")
    _remove_mesh(analysis, "ReducedMesh")
    feature, info = _mesh_feature(analysis, td.read_mesh(mesh_path), mesh_path, None, "ReducedMesh")
    _result_file(analysis, feature, outputs["reduced_result"], outputs["reduced_model"], "ReducedMeshResult")
    merged = merged_nodes.show_from_model_file(analysis, feature, outputs["reduced_model"])
    analysis.ReducedModelFile = outputs["reduced_model"]
    report = _read_json(os.path.join(folder, "report.json"))
    info.update({k: report[k] for k in ("faces_before", "faces_after", "tolerance_K", "noise_floor_K",
                                        "max_temperature_difference_K", "trials") if k in report})
    info["report"] = os.path.join(folder, "report.json")
    info["merged_nodes"] = {m.MergedName: list(m.Members) for m in merged}
    if summary:
        FreeCAD.Console.PrintMessage(summary.rstrip() + "\n")
    _progress("reduced %d -> %d faces, max |dT| %.3g K (tolerance %.3g K)" % (
        info.get("faces_before", 0), info.get("faces_after", 0), info.get("max_temperature_difference_K", 0.0),
        info.get("tolerance_K", 0.0)))
    return feature, info
