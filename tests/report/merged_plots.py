"""Plots of a merged model name its merged nodes and list their members: `thermodec merge` joins
nodes of the sample, `simulate --plot` draws the merged model (PNG written) and the plot script,
run on the same data with its figure captured, labels the curves by merged node and lists each
merged node's members under the plot.

usage: merged_plots.py THERMODEC MODEL PLOTS_DIR WORKDIR
"""
import json
import os
import runpy
import subprocess
import sys

thermodec, model, plots_dir, work = sys.argv[1:5]
os.makedirs(work, exist_ok=True)


def run(*args):
    r = subprocess.run([thermodec, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("thermodec %s failed: %s" % (" ".join(args), r.stderr))


merged = os.path.join(work, "merged.json")
run("merge", model, "--group", "body_px,body_py,body_pz", "--group", "wing_py,wing_my", "-o", merged)
result, png = os.path.join(work, "result.json"), os.path.join(work, "temperatures.png")
run("simulate", merged, "--json", result, "--plot", png, "--rays", "200", "--noise-target", "0", "-q")
failures = []
if not os.path.getsize(png) > 10000:
    failures.append("no plot written: %s" % png)

sys.path.insert(0, plots_dir)
import _common  # noqa: E402

captured = {}


def capture(fig, out):
    captured["legend"] = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    captured["notes"] = [t.get_text() for t in fig.texts]
    _common.plt.close(fig)


_common.save = capture
sys.argv = ["temperatures.py", result, os.path.join(work, "unused.png")]
runpy.run_path(os.path.join(plots_dir, "temperatures.py"))
for name in ("body_px+2", "wing_py+1"):
    if name not in captured["legend"]:
        failures.append("curve of %s not labelled: legend %s" % (name, captured["legend"]))
note = " ".join(captured["notes"])
for expected in ("body_px+2 = body_px + body_py + body_pz", "wing_py+1 = wing_py + wing_my"):
    if expected not in note:
        failures.append("members not listed: %r not in %r" % (expected, note))
# A merged node of 20 members: its first five and the count of the rest, not a line off the page.
import _style  # noqa: E402

many = {"m%02d" % k: "m00+19" for k in range(20)}
fig = _common.plt.figure()
_style.note_merged(fig, many)
long_note = fig.texts[0].get_text()
if "m00+19 = m00 + m01 + m02 + m03 + m04 \u2026 (+15 more)" not in long_note or "m05" in long_note:
    failures.append("a long member list is not cut: %r" % long_note)
print("legend: %s\nnote: %s\nlong: %s" % (", ".join(captured["legend"]), note, long_note))
if failures:
    sys.exit("\n".join(failures))
