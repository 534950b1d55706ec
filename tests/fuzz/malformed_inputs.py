#!/usr/bin/env python3
"""Malformed inputs never crash the CLI: seeded mutations of the sample satellite's OBJ and
model.json (bytes flipped, cut, truncated, 'nan'/'inf'/huge numbers spliced in; JSON values
replaced by wrong types, negatives, zeros, huge values, or deleted) are fed to `info`,
`simulate` (few rays) and `decimate`. Every run must exit 0 (input still valid) or 1 (a clear
error message on stderr), never by a signal or another code, and a simulation that succeeds
must not write NaN. Deterministic: the seed is fixed.

    malformed_inputs.py THERMODEC_CLI SAMPLE_DIR [cases]
"""
import copy
import json
import os
import random
import subprocess
import sys
import tempfile

cli, sample = sys.argv[1], sys.argv[2]
cases = int(sys.argv[3]) if len(sys.argv) > 3 else 24
rng = random.Random(20261123)
obj = open(os.path.join(sample, "satellite.obj"), "rb").read()
model = json.load(open(os.path.join(sample, "model.json")))
DELETE = object()


def mutate_bytes(data):
    b = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        op, i = rng.random(), rng.randrange(len(b))
        if op < 0.3:
            b[i] = rng.randrange(256)
        elif op < 0.55:
            del b[i:i + rng.randint(1, 200)]
        elif op < 0.8:
            b[i:i] = rng.choice([b"nan", b"-1", b"1e308", b"inf", b" 999999 ", b"\n", b"f 1 1 1\n", b"v 0 0 0\n"])
        else:
            b = b[:i]
    return bytes(b)


def leaves(j, path=()):
    if isinstance(j, dict):
        for k, v in j.items():
            yield from leaves(v, path + (k,))
    elif isinstance(j, list):
        for i, v in enumerate(j):
            yield from leaves(v, path + (i,))
    else:
        yield path


def mutate_json(j):
    j = copy.deepcopy(j)
    for _ in range(rng.randint(1, 3)):
        paths = list(leaves(j))
        if not paths:
            break
        path = rng.choice(paths)
        value = rng.choice([DELETE, -1, 0, 1e308, -1e-300, "x", None, [], {}, 2 ** 40, 0.5, 1e6, -273.2, True])
        parent = j
        for p in path[:-1]:
            parent = parent[p]
        if value is DELETE:
            del parent[path[-1]]
        else:
            parent[path[-1]] = value
    return json.dumps(j).encode()


failures = []
with tempfile.TemporaryDirectory(prefix="thermodec_fuzz_") as root:
    for case in range(cases):
        d = os.path.join(root, str(case))
        os.makedirs(d)
        open(os.path.join(d, "satellite.obj"), "wb").write(obj if case % 2 else mutate_bytes(obj))
        open(os.path.join(d, "model.json"), "wb").write(mutate_json(model) if case % 2 else json.dumps(model).encode())
        target = os.path.join(d, "model.json" if case % 4 != 2 else "satellite.obj")
        out = os.path.join(d, "out.json")
        for args in (["info", target],
                     ["simulate", "-q", "--rays", "20", "--earth-rays", "16", "--sun-rays", "16", "--noise-target", "0",
                      target, "--json", out],
                     ["decimate", target, "--ratio", "0.5", "-o", os.path.join(d, "half.json")]):
            p = subprocess.run([cli] + args, capture_output=True, timeout=300)
            if p.returncode not in (0, 1):
                failures.append(f"case {case} {args[0]}: exit {p.returncode}: {p.stderr[-400:]!r}")
            elif p.returncode == 1 and not p.stderr.strip():
                failures.append(f"case {case} {args[0]}: exit 1 without a message")
            elif p.returncode == 0 and args[0] == "simulate" and "NaN" in open(out).read():
                failures.append(f"case {case} simulate: NaN in the result")


def cube(c, fmt):
    """A cube with corners at +-c: OBJ text, or a NASTRAN deck (free field)."""
    corners = [((-1) ** (1 - (i & 1)), (-1) ** (1 - ((i >> 1) & 1)), (-1) ** (1 - ((i >> 2) & 1))) for i in range(8)]
    faces = [(1, 3, 4), (1, 4, 2), (5, 6, 8), (5, 8, 7), (1, 2, 6), (1, 6, 5),
             (3, 7, 8), (3, 8, 4), (1, 5, 7), (1, 7, 3), (2, 4, 8), (2, 8, 6)]
    sgn = lambda s: "" if s > 0 else "-"
    if fmt == "obj":
        return "".join(f"v {sgn(x)}{c} {sgn(y)}{c} {sgn(z)}{c}\n" for x, y, z in corners) + \
            "".join(f"f {a} {b} {d}\n" for a, b, d in faces)
    return "BEGIN BULK\n" + "".join(f"GRID,{i + 1},,{sgn(x)}{c},{sgn(y)}{c},{sgn(z)}{c}\n" for i, (x, y, z) in enumerate(corners)) + \
        "".join(f"CTRIA3,{k + 1},1,{a},{b},{d}\n" for k, (a, b, d) in enumerate(faces)) + "ENDDATA\n"


# Hostile inputs found by a fault audit: geometry whose areas overflow, names carrying terminal
# escapes and direction overrides, duplicated and negative NASTRAN ids, a deck cut short, binary
# bytes and a huge field. Each must be refused (or read) with a message free of control bytes.
hostile = {
    "far.obj": "v 1e308 0 0\nv -1e308 0 0\nv 0 1e308 0\nf 1 2 3\n",
    "cube308.obj": cube("1e308", "obj"),
    "cube30.obj": cube("1e30", "obj"),
    "cube308.bdf": cube("1.+308", "bdf"),
    "escape.bdf": cube("1.", "bdf").replace("BEGIN BULK\n", "BEGIN BULK\n$ thermodec node 1 \x1b[2J\x1b]0;x\x07rad\u202eiator\n"),
    "escape.obj": "g \x1b[31mred\u202e\n" + cube("1", "obj"),
    "duplicate.bdf": cube("1.", "bdf").replace("ENDDATA", "CTRIA3,3,1,1,2,6\nENDDATA"),
    "negative.bdf": cube("1.", "bdf").replace("GRID,1,", "GRID,-1,").replace(",1,3,4", ",-1,3,4"),
    "cut.bdf": cube("1.", "bdf").replace("ENDDATA\n", ""),
    "binary.bdf": cube("1.", "bdf").replace("BEGIN BULK\n", "BEGIN BULK\nGRID,1,,".encode().decode("latin-1") +
                                           "".join(chr(i) for i in range(256)) + "\n" + "Z" * (1 << 20) + ",1\n"),
}
with tempfile.TemporaryDirectory(prefix="thermodec_hostile_") as root:
    for name, text in hostile.items():
        path = os.path.join(root, name)
        open(path, "wb").write(text.encode("utf-8", "surrogateescape") if name != "binary.bdf" else text.encode("latin-1"))
        for args in (["info", path],
                     ["simulate", "-q", "--rays", "20", "--earth-rays", "16", "--sun-rays", "16", "--noise-target", "0", path]):
            p = subprocess.run([cli] + args, capture_output=True, timeout=300)
            said = p.stdout + p.stderr
            if p.returncode not in (0, 1):
                failures.append(f"{name} {args[0]}: exit {p.returncode}: {p.stderr[-400:]!r}")
            elif any(b < 0x20 and b != 0x0a for b in said) or b"\x7f" in said or "\u202e".encode() in said:
                failures.append(f"{name} {args[0]}: control characters in the output: {said[:300]!r}")
            elif len(p.stderr) > 4000:
                failures.append(f"{name} {args[0]}: {len(p.stderr)} bytes of messages")
    cases += len(hostile)

print(f"{cases} mutated and hostile inputs: {len(failures)} failure(s)")
for f in failures:
    print(f)
sys.exit(1 if failures else 0)
