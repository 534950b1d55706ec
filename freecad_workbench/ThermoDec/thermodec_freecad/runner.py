"""Long runs (tessellate, simulate, reduce, decimate, export) as processes, so FreeCAD's GUI stays live.

As FreeCAD FEM runs its solvers: the job is a list of command lines (built headless by
`tessellate_job` / `reduce_job` / `export_job` ..., testable without a GUI); the GUI side (`Runner`) starts them one
after the other with QProcess, shows their output lines as progress, can cancel (kills the
process) and, when the last one succeeded, calls back on the main thread to import the results.
The CLI is the same core and the same simulation as the Python module's functions; the
tessellation runs the workbench's own meshing in `freecadcmd`.
"""

import os
import shutil
import time

from . import core, export
from .errors import ThermoDecError


def cli_path():
    """The `thermodec` executable: $THERMODEC_CLI, else beside the build tree's Python module
    (build/core/thermodec), else on PATH. Raises ThermoDecError naming what was tried."""
    tried = []
    env = os.environ.get("THERMODEC_CLI")
    if env:
        if os.access(env, os.X_OK):
            return env
        tried.append(env)
    try:
        module_dir = os.path.dirname(os.path.abspath(core.module().__file__))
        # build tree: build/python + build/core; installed: <prefix>/share/freecad/Mod/ThermoDec + <prefix>/bin
        for candidate in (os.path.join(module_dir, os.pardir, "core", "thermodec"),
                          os.path.join(module_dir, os.pardir, os.pardir, os.pardir, os.pardir, "bin", "thermodec")):
            if os.access(candidate, os.X_OK):
                return os.path.normpath(candidate)
            tried.append(os.path.normpath(candidate))
    except ThermoDecError:
        pass
    found = shutil.which("thermodec")
    if found:
        return found
    raise ThermoDecError("the thermodec command is not found (tried %s and PATH): build the thermodec target, "
                         "install it, or set THERMODEC_CLI" % (", ".join(tried) or "THERMODEC_CLI"))


def freecadcmd_path():
    """FreeCAD's console executable (for the background tessellation): $THERMODEC_FREECADCMD,
    else beside this FreeCAD (its bin/ folder), else freecadcmd / FreeCADCmd on PATH."""
    env = os.environ.get("THERMODEC_FREECADCMD")
    if env:
        return env
    import FreeCAD
    home = os.path.join(FreeCAD.getHomePath(), "bin")
    for name in ("FreeCADCmd", "freecadcmd", "freecadcmd-python3"):
        if os.access(os.path.join(home, name), os.X_OK):
            return os.path.join(home, name)
    for name in ("freecadcmd", "FreeCADCmd"):
        if shutil.which(name):
            return shutil.which(name)
    raise ThermoDecError("FreeCAD's console program (freecadcmd) is not found in %s or on PATH: set "
                         "THERMODEC_FREECADCMD" % home)


class Job:
    """Command lines to run in order, with a title per step, and the files they produce."""

    def __init__(self, title):
        self.title = title
        self.steps = []     # [(title, argv)]
        self.outputs = {}   # name -> path, read by the job's finish function

    def add(self, title, argv):
        self.steps.append((title, [str(a) for a in argv]))


def reduce_job(analysis, tolerance_K=None, strategy=None, cases=None, plots=True):
    """The Reduce command as CLI steps: export the analysis (now, on the caller's thread: it
    reads the document), simulate the dense model unless its result is current, `thermodec
    reduce`, then simulate the reduced model for the reduced-vs-original plot."""
    cli = cli_path()
    json_path, _ = export.write_model(analysis, export.default_paths(analysis)[0])
    folder = os.path.dirname(json_path)
    reduced = os.path.join(folder, "reduced")
    tolerance_K = analysis.ToleranceK if tolerance_K is None else float(tolerance_K)
    strategy = strategy or analysis.ReductionStrategy
    cases = list(analysis.LoadCases) if cases is None else list(cases)
    job = Job("Reduce")
    dense_result = os.path.join(folder, "result.json")
    from . import results
    current = results.dense_result_current(analysis)
    if current != dense_result:  # Simulate's result of these same inputs is reused
        job.add("simulate the dense model", [cli, "simulate", json_path, "--json", dense_result])
    argv = [cli, "reduce", json_path, "--tolerance", repr(tolerance_K), "--strategy", strategy, "--out", reduced]
    for c in cases:
        argv += ["--case", c]
    if getattr(analysis, "MergeNodes", False):
        argv.append("--merge-nodes")
    if not plots:
        argv.append("--no-plots")
    job.add("reduce (tolerance %.3g K, %s)" % (tolerance_K, strategy), argv)
    reduced_model = os.path.join(reduced, "model.json")
    reduced_result = os.path.join(reduced, "result.json")
    job.add("simulate the reduced model", [cli, "simulate", reduced_model, "--json", reduced_result])
    job.outputs.update(model=json_path, result=dense_result, simulate_dense=current != dense_result, folder=reduced, reduced_model=reduced_model,
                       reduced_result=reduced_result, tolerance_K=tolerance_K)
    return job


def tessellate_job(analysis, max_edge_mm=None):
    """The Tessellate command as a background step: the shapes and their face assignment are
    written now (on the caller's thread: it reads the document; assignment errors are raised
    here), `freecadcmd` meshes them (tessellate_worker.py), and tessellate.import_job stores
    the mesh when it ends. The mesh is the one tessellate.tessellate makes in-process."""
    from . import tessellate
    folder = os.path.join(os.path.dirname(export.default_paths(analysis)[0]), "tessellation")
    outputs = tessellate.write_job(analysis, folder, max_edge_mm)
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    paths = [package]
    try:
        paths.append(os.path.dirname(os.path.abspath(core.module().__file__)))  # thermodec, for the weld
    except ThermoDecError:
        pass
    code = "import sys; sys.path[:0] = %r; from thermodec_freecad import tessellate_worker; " \
           "tessellate_worker.main(%r)" % (paths, outputs["job"])
    job = Job("Tessellate")
    job.add("mesh %d B-rep faces (max edge %.4g mm)" % (outputs["faces"], outputs["max_edge_mm"]),
            [freecadcmd_path(), "-c", code])
    job.outputs.update(outputs)
    return job


def simulate_job(analysis):
    """The Simulate command as a CLI step: export the analysis (now, on the caller's thread: it
    reads the document), then `thermodec simulate --json result.json` beside the model (the
    same simulation as thermodec.simulate_model, bit for bit)."""
    cli = cli_path()
    json_path, _ = export.write_model(analysis, export.default_paths(analysis)[0])
    result = os.path.join(os.path.dirname(json_path), "result.json")
    job = Job("Simulate")
    job.add("simulate the model", [cli, "simulate", json_path, "--json", result])
    job.outputs.update(model=json_path, result=result)
    return job


def decimate_job(analysis, global_ratio=None):
    """The Decimate command as a CLI step: export the analysis (now, on the caller's thread),
    then `thermodec decimate --ratio` into reduced/model.json + model.obj beside it (the
    decimation results.decimate runs in-process); results.import_decimation imports it."""
    cli = cli_path()
    ratio = analysis.GlobalRatio if global_ratio is None else float(global_ratio)
    json_path, _ = export.write_model(analysis, export.default_paths(analysis)[0])
    out = os.path.join(os.path.dirname(json_path), "reduced", "model.json")
    job = Job("Decimate")
    job.add("decimate (remove %.3g %% of the faces)" % (100 * ratio), [cli, "decimate", json_path, "--ratio", repr(ratio),
                                                                      "--output", out])
    job.outputs.update(model=json_path, reduced_model=out, mesh=os.path.join(os.path.dirname(out), "model.obj"),
                       global_ratio=ratio)
    return job


def export_job(analysis, fmt, out, model_path=None):
    """`thermodec export` of the reduced model when the analysis has a current one (else the
    dense model, exported now) to `fmt` at `out`."""
    from . import results
    cli = cli_path()
    if model_path is None:
        model_path = results.model_for_tools(analysis)
    job = Job("Export for other tools")
    job.add("export %s as %s" % (os.path.basename(os.path.dirname(model_path)) == "reduced" and "the reduced model"
                                 or "the dense model", fmt), [cli, "export", model_path, "--format", fmt, "--output", out])
    job.outputs.update(model=model_path, out=out, format=fmt)
    return job


#: How far into `thermodec reduce` its stage lines are (a rough share of its time, for a progress
#: bar: the sensitivity sweep, node by node, dominates; --merge-nodes merges first: its lines
#: run up to 0.1, and the panel keeps the largest share seen). Matched in order; None: no change.
_REDUCE_STAGES = (("node merging: simulating", 0.01), ("node merging: the first", 0.09), ("node merging: ", 0.03),
                  ("merged (", 0.06), ("sampling", 0.02), ("reference", 0.05), ("noise floor", 0.10),
                  ("decimation", 0.13), ("sensitivity analysis", 0.15), ("prediction and reduction", 0.72),
                  ("push", 0.78), ("back-off", 0.78), ("verify", 0.85), ("verification", 0.9))


def stage_fraction(line):
    """Share [0, 1] of a `thermodec reduce` run (or a background tessellation) done when it
    prints `line`, or None."""
    import re
    m = re.match(r"tessellate: (\d+)/(\d+) faces", line)
    if m:
        return int(m.group(1)) / max(int(m.group(2)), 1)
    text = line.split("] ", 1)[-1] if line.startswith("reduce: [") else line[len("reduce: "):] \
        if line.startswith("reduce: ") else ""
    text = text.lstrip()  # sub-stages are indented ("  sensitivity: 3/11 nodes swept")
    m = re.match(r"sensitivity: (\d+)/(\d+) nodes", text)
    if m:
        return 0.15 + 0.55 * int(m.group(1)) / max(int(m.group(2)), 1)
    for key, share in _REDUCE_STAGES:
        if text.startswith(key):
            return share
    return None


def run_blocking(job, log=None):
    """Runs the job's steps here (headless scripts and tests). Raises ThermoDecError with the
    failing step's last output lines."""
    import subprocess
    for title, argv in job.steps:
        if log:
            log("%s: %s" % (title, " ".join(argv)))
        done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if log:
            for line in done.stdout.splitlines()[-12:]:
                log(line)
        if done.returncode != 0:
            raise ThermoDecError("%s failed (exit %d): %s" % (title, done.returncode,
                                                              " | ".join(done.stdout.strip().splitlines()[-3:])))
    return job


class Runner:
    """Runs a Job with QProcess (GUI): `on_line(text)` for every output line, `on_done(ok,
    message)` when the last step ends, fails or is cancelled. All callbacks on the main thread."""

    def __init__(self, job, on_line, on_done):
        self.job, self.on_line, self.on_done = job, on_line, on_done
        self.index = -1
        self.process = None
        self.cancelled = False
        self.started = time.monotonic()
        self.tail = []

    def start(self):
        self._next()

    @property
    def step_title(self):
        return self.job.steps[self.index][0] if 0 <= self.index < len(self.job.steps) else ""

    def _next(self):
        from PySide import QtCore
        self.index += 1
        if self.index >= len(self.job.steps):
            self.on_done(True, "%s done in %.0f s" % (self.job.title, time.monotonic() - self.started))
            return
        title, argv = self.job.steps[self.index]
        self.on_line("[%d/%d] %s" % (self.index + 1, len(self.job.steps), title))
        self.process = QtCore.QProcess()
        self.process.setProcessChannelMode(QtCore.QProcess.MergedChannels)
        self.process.readyReadStandardOutput.connect(self._read)
        self.process.finished.connect(self._finished)
        self.process.errorOccurred.connect(self._error)
        self.process.start(argv[0], argv[1:])

    def _error(self, error):
        from PySide import QtCore
        if error == QtCore.QProcess.FailedToStart:  # no finished signal follows
            self.on_done(False, "%s: cannot start %s" % (self.step_title, self.job.steps[self.index][1][0]))

    def _read(self):
        data = bytes(self.process.readAllStandardOutput()).decode("utf-8", "replace")
        for line in data.splitlines():
            if line.strip():
                self.tail = (self.tail + [line])[-3:]
                self.on_line(line)

    def _finished(self, code, status=None):
        self._read()
        if self.cancelled:
            self.on_done(False, "%s cancelled during: %s" % (self.job.title, self.step_title))
        elif code != 0:
            self.on_done(False, "%s failed (exit %d): %s" % (self.step_title, code, " | ".join(self.tail)))
        else:
            self._next()

    def cancel(self):
        self.cancelled = True
        if self.process is not None:
            self.process.kill()

    def running(self):
        from PySide import QtCore
        return self.process is not None and self.process.state() != QtCore.QProcess.NotRunning
