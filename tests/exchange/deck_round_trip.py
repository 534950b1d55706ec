"""Exported decks integrated from the file alone, as the target tool integrates them, reproduce
`thermodec simulate`.

ESATAN-TMS (.d): nodes, GL/GR, STEFAN, PERIOD and the doublet tables QSOLn/QALBn/QEIRn (and
QINTn, a node's internal power schedule) that $VARIABLES1 reads with INTCY1 (cyclic linear
interpolation); one orbit integrated from the deck's initial temperatures (the periodic state
SOLCYC converges to). Run on MODEL and on a copy of it whose `instrument` node (if any) has a
square-wave `power_schedule_W` instead of its constant power.
SINDA/FLUINT (.inp): node and conductor data, SIGMA, the arrays D11CYL reads (cyclic linear),
TIMEND; integrated from the initial temperatures over TIMEND, the last orbit compared.
CSV: the nodes, couplings and loads tables alone (capacitances, fixed nodes, sink, period).

The integrator is scipy's Radau (implicit Runge-Kutta, order 5) with tight tolerances, run
piecewise between table points, where the loads are linear. Every node at every `simulate`
position must agree within 0.05 K; the decks' periodicity residual within 0.05 K too.

usage: deck_round_trip.py THERMODEC MODEL WORKDIR
Exit 77 (CTest SKIP_RETURN_CODE) when numpy or scipy is missing.
"""
import json
import os
import re
import subprocess
import sys

try:
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError as e:
    print("SKIP: python module missing: %s (apt-get install python3-scipy: scripts/setup does)" % e)
    sys.exit(77)

TOLERANCE_K = 0.05
thermodec, model, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
# Few rays: the decks carry whatever the simulation found, exactly; the sampling does not matter.
FAST = ["--rays", "400", "--noise-target", "0", "-q"]


def run(*args):
    r = subprocess.run([thermodec, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("thermodec %s failed: %s" % (" ".join(args), r.stderr))


def fnum(s):
    return float(s.strip().replace("D", "E").replace("d", "e"))


class Network:
    """C dT/dt = Q(t) + sum GL (Tj - Ti) + sigma sum GR (Tj^4 - Ti^4); fixed nodes held."""

    def __init__(self, n):
        self.C = np.zeros(n)
        self.QI = np.zeros(n)
        self.fixed = np.full(n, np.nan)
        self.T0 = np.zeros(n)
        self.GL = np.zeros((n, n))
        self.GR = np.zeros((n, n))
        self.GRs = np.zeros(n)
        self.sink = 2.7
        self.sigma = 5.670374419e-8
        self.period = 0.0
        self.table_t = None  # K times in [0, P)
        self.table_q = None  # n x K external loads [W]
        self.extra = []  # (node, times over [0, P], W): other cyclic tables (power schedules)

    def loads(self, t):
        """Cyclic linear interpolation of the tables (INTCY1 / D11CYL)."""
        tt = np.concatenate([self.table_t, [self.period]])
        qq = np.concatenate([self.table_q, self.table_q[:, :1]], axis=1)
        x = t % self.period
        q = np.array([np.interp(x, tt, q) for q in qq])
        for i, et, ev in self.extra:
            q[i] += np.interp(x, et, ev)
        return q

    def integrate(self, T0, t_end, out_times):
        free = np.isnan(self.fixed)
        if np.any(free & (self.C <= 0)):
            sys.exit("arithmetic nodes are not handled by this reader")
        T = np.where(free, T0, self.fixed)
        G = self.GL.copy()
        np.fill_diagonal(G, 0)
        R = self.GR.copy()
        np.fill_diagonal(R, 0)
        s = self.sigma

        def f(t, y, q0, q1, t0, t1):
            T = np.where(free, 0, self.fixed)
            T[free] = y
            q = q0 + (q1 - q0) * (t - t0) / (t1 - t0)
            T4 = T ** 4
            heat = self.QI + q + G @ T - G.sum(1) * T + s * (R @ T4 - R.sum(1) * T4) + s * self.GRs * (self.sink ** 4 - T4)
            return heat[free] / self.C[free]

        def jac(t, y, q0, q1, t0, t1):
            T = np.where(free, 0, self.fixed)
            T[free] = y
            J = G - np.diag(G.sum(1)) + 4 * s * (R * T ** 3 - np.diag((R.sum(1) + self.GRs) * T ** 3))
            return J[np.ix_(free, free)] / self.C[free][:, None]

        # Pieces between table points (repeated every orbit) and the output times.
        orbits = int(round(t_end / self.period))
        cuts = sorted(set(np.round(np.concatenate(
            [k * self.period + np.concatenate([self.table_t, out_times] + [e[1] for e in self.extra])
             for k in range(orbits)] + [[t_end]]), 9)))
        y = T[free]
        states = {0.0: T.copy()}
        for a, b in zip(cuts[:-1], cuts[1:]):
            if b - a < 1e-9:
                continue
            # Loads just after a and just before b: linear in between (no table point inside).
            eps = 1e-7 * (b - a)
            q0, q1 = self.loads(a + eps), self.loads(b - eps)
            args = (q0, q1, a + eps, b - eps)
            sol = solve_ivp(f, (a, b), y, method="Radau", jac=jac, rtol=1e-10, atol=1e-9, args=args)
            if not sol.success:
                sys.exit("integration failed: " + sol.message)
            y = sol.y[:, -1]
            T = np.where(free, 0, self.fixed)
            T[free] = y
            states[round(b, 9)] = T.copy()
        return states


def read_esatan(path):
    text = open(path).read()
    nodes = re.findall(r"^([DAB])(\d+) = '((?:[^']|'')*)'(.*);$", text, re.M)
    ids = sorted(int(n[1]) for n in nodes if int(n[1]) != 99999)
    net = Network(len(ids))
    for kind, nid, name, rest in nodes:
        attrs = dict((k.strip(), fnum(v)) for k, v in re.findall(r"(\w+) = ([^,;]+)", rest))
        i = int(nid) - 1
        if int(nid) == 99999:
            net.sink = attrs["T"]
            continue
        net.C[i] = attrs.get("C", 0.0)
        net.QI[i] = attrs.get("QI", 0.0)
        net.T0[i] = attrs["T"]
        if kind == "B":
            net.fixed[i] = attrs["T"]
    for kind, i, j, v in re.findall(r"^(GL|GR)\((\d+), (\d+)\) = ([^;]+);", text, re.M):
        i, j, v = int(i) - 1, int(j) - 1, fnum(v)
        if kind == "GL":
            net.GL[i, j] += v
            net.GL[j, i] += v
        elif j == 99998:
            net.GRs[i] += v
        else:
            net.GR[i, j] += v
            net.GR[j, i] += v
    net.sigma = fnum(re.search(r"^STEFAN = ([^;]+);", text, re.M).group(1))
    net.period = fnum(re.search(r"^PERIOD = ([^;]+);", text, re.M).group(1))
    arrays = {}
    for name, body in re.findall(r"^([A-Z]+\d+)\(\d+\) =\n([^;]*);", text, re.M):
        v = [fnum(x) for x in body.replace("\n", " ").split(",")]
        arrays[name] = (np.array(v[0::2]), np.array(v[1::2]))
    uses = re.findall(r"Q[SAE]\((\d+)\) = INTCY1\(TIMEM, ([A-Z]+\d+), PERIOD\)", text)
    if not uses:
        sys.exit("ESATAN deck: no INTCY1 load tables")
    t = arrays[uses[0][1]][0][:-1]
    net.table_t = t
    net.table_q = np.zeros((len(ids), len(t)))
    for i, name in uses:
        tt, vv = arrays[name]
        if not np.array_equal(tt[:-1], t):
            sys.exit("ESATAN deck: tables with different times")
        net.table_q[int(i) - 1] += vv[:-1]
    for i, name in re.findall(r"QI\((\d+)\) = INTCY1\(TIMEM, ([A-Z]+\d+), PERIOD\)", text):
        net.extra.append((int(i) - 1, *arrays[name]))
    return net


def read_sinda(path):
    text = open(path).read()
    blocks = dict(re.findall(r"^HEADER ([A-Z0-9 ]+?)(?:,[^\n]*)?\n(.*?)(?=^HEADER |^END OF DATA)", text, re.M | re.S))
    rows = []
    for line in blocks["NODE DATA"].splitlines():
        data = line.split("$")[0].strip()
        if data:
            rows.append([float(x) for x in data.split(",")])
    n = max(abs(int(r[0])) for r in rows if abs(int(r[0])) != 99999)
    net = Network(n)
    for nid, T, C in rows:
        i = abs(int(nid)) - 1
        if abs(int(nid)) == 99999:
            net.sink = T
            continue
        net.T0[i] = T
        net.C[i] = C if C > 0 else 0.0
        if nid < 0:
            net.fixed[i] = T
    for line in blocks["CONDUCTOR DATA"].splitlines():
        v = [float(x) for x in line.split(",")] if line.strip() else []
        if len(v) != 4:
            continue
        i, j = int(v[1]) - 1, int(v[2]) - 1
        if v[0] > 0:
            net.GL[i, j] += v[3]
            net.GL[j, i] += v[3]
        elif j == 99998:
            net.GRs[i] += v[3]
        else:
            net.GR[i, j] += v[3]
            net.GR[j, i] += v[3]
    control = blocks["CONTROL DATA"]
    net.sigma = float(re.search(r"SIGMA\s*=\s*(\S+)", control).group(1))
    t_end = float(re.search(r"TIMEND\s*=\s*(\S+)", control).group(1))
    arrays = {}
    for aid, body in re.findall(r"^\s+(\d+) =(.*?)(?=^\s+\d+ =|\Z)", blocks["ARRAY DATA"], re.M | re.S):
        v = [float(x) for x in body.replace("\n", " ").replace(",", " ").split()]
        arrays[int(aid)] = (np.array(v[0::2]), np.array(v[1::2]))
    t = None
    for i, qi, aid, period in re.findall(r"Q(\d+) = (\S+) \+ D11CYL\(TIMEN, A(\d+), ([^)]+)\)", blocks["VARIABLES 1"]):
        i = int(i) - 1
        net.QI[i] = float(qi)
        net.period = float(period)
        tt, vv = arrays[int(aid)]
        if t is None:
            t = tt[:-1]
            net.table_q = np.zeros((n, len(t)))
        net.table_q[i] = vv[:-1]
    net.table_t = t
    if "CALL STEADY" in blocks["OPERATIONS"] and "CALL TRANSIENT" in blocks["OPERATIONS"]:
        sys.exit("SINDA deck: STEADY before TRANSIENT replaces the periodic initial state")
    return net, t_end


def read_csv(prefix):
    def rows(path):
        lines = [l.rstrip("\n") for l in open(path) if not l.startswith("#")]
        head = lines[0].split(",")
        return [dict(zip(head, l.split(","))) for l in lines[1:]]

    nodes = rows(prefix + "_nodes.csv")
    names = [r["node"] for r in nodes if r["node"] != "space"]
    index = {name: i for i, name in enumerate(names)}
    net = Network(len(names))
    for r in nodes:
        if r["node"] == "space":
            net.sink = float(r["fixed_temperature_K"])
            continue
        i = index[r["node"]]
        net.C[i] = float(r["capacitance_J_per_K"])
        net.QI[i] = float(r["internal_W"])
        net.T0[i] = float(r["initial_temperature_K"])
        net.period = float(r["period_s"])
        if r["kind"] == "boundary":
            net.fixed[i] = float(r["fixed_temperature_K"])
    for r in rows(prefix + "_couplings.csv"):
        i, v = index[r["from"]], float(r["value"])
        if r["to"] == "space":
            net.GRs[i] += v
            continue
        j = index[r["to"]]
        M = net.GL if r["type"] == "GL" else net.GR
        M[i, j] += v
        M[j, i] += v
    loads = rows(prefix + "_loads.csv")
    t = sorted(set(float(r["time_s"]) for r in loads))
    col = {x: k for k, x in enumerate(t)}
    net.table_t = np.array(t)
    net.table_q = np.zeros((len(names), len(t)))
    for r in loads:
        net.table_q[index[r["node"]], col[float(r["time_s"])]] = (
            float(r["solar_W"]) + float(r["albedo_W"]) + float(r["earth_ir_W"]))
    return net, names


failures = []


def compare(what, net, t_end, names, ref):
    times = np.array(ref["times_s"])
    states = net.integrate(net.T0, t_end, times)
    last = t_end - net.period
    worst, where = 0.0, ""
    for k, t in enumerate(times):
        T = states[round(last + t, 9)]
        for i, name in enumerate(names):
            d = abs(T[i] - ref["temperatures_K"][name][k])
            if d > worst:
                worst, where = d, "%s at t = %.1f s" % (name, t)
    periodic = np.max(np.abs(states[round(t_end, 9)] - states[round(last, 9)]))
    print("%s: max |T(file) - T(simulate)| = %.4f K (%s), periodicity residual %.4f K, %d table points"
          % (what, worst, where, periodic, len(net.table_t)))
    if not worst <= TOLERANCE_K:
        failures.append("%s differs from simulate by %.4f K (%s)" % (what, worst, where))
    if not periodic <= TOLERANCE_K:
        failures.append("%s is not periodic: %.4f K" % (what, periodic))


ref_path = os.path.join(work, "simulate.json")
run("simulate", model, "--json", ref_path, *FAST)
ref = json.load(open(ref_path))
names = ref["nodes"]
for fmt, out in (("esatan", "sat.d"), ("sinda", "sat.inp"), ("csv", "sat")):
    run("export", model, "-f", fmt, "-o", os.path.join(work, out), *FAST)

net = read_esatan(os.path.join(work, "sat.d"))
compare("ESATAN (INTCY1)", net, net.period, names, ref)

# The same with an internal power schedule on `instrument` (0.2, 1.8, 1 x its power: up to 3 K off the constant).
m = json.load(open(model))
if "instrument" in m.get("nodes", {}) and m.get("environment", {}).get("type") == "orbit":
    m["mesh"] = os.path.join(os.path.dirname(os.path.abspath(model)), m["mesh"])
    q = m["nodes"]["instrument"].pop("power", 0.0)
    m["nodes"]["instrument"]["power_schedule_W"] = [[0.0, 0.2 * q], [1000.0, 1.8 * q], [3000.0, q]]
    scheduled = os.path.join(work, "scheduled.json")
    json.dump(m, open(scheduled, "w"))
    ref_s_path = os.path.join(work, "scheduled_simulate.json")
    run("simulate", scheduled, "--json", ref_s_path, *FAST)
    run("export", scheduled, "-f", "esatan", "-o", os.path.join(work, "scheduled.d"), *FAST)
    net = read_esatan(os.path.join(work, "scheduled.d"))
    if not net.extra:
        failures.append("ESATAN deck: the power schedule's QINT table is missing")
    compare("ESATAN with a power schedule", net, net.period, names, json.load(open(ref_s_path)))
net, t_end = read_sinda(os.path.join(work, "sat.inp"))
compare("SINDA (D11CYL, %g orbits)" % round(t_end / net.period), net, t_end, names, ref)
net, csv_names = read_csv(os.path.join(work, "sat"))
if csv_names != names:
    failures.append("CSV nodes %s differ from simulate's %s" % (csv_names, names))
compare("CSV tables", net, net.period, names, ref)

if failures:
    print("\n".join("FAIL: " + f for f in failures))
    sys.exit(1)
print("all decks reproduce simulate within %.2g K" % TOLERANCE_K)
