#!/usr/bin/env python3
"""Peer check of `dem clump --export`: loads the exports of clump templates in YADE and LAMMPS
and compares the mass, mass centre and moment of inertia I_z that each peer computes with the
template's (docs/exports.md). PFC2D and MercuryDPM are not installable here: their files are read
back as those codes read them (MercuryDPM: single precision, std::stof) and compared the same way.

Usage: peer_check.py TEMPLATE.json...   (the exports lie beside each template)
Prints one table row per grain and peer path; exits 1 on a mismatch, 2 on a usage or peer error.
Tolerances: mass and I_z relative 1e-9 (the peers' eigen-solvers and sums round at ~1e-15);
mass centre 1e-9 R_eq. A row whose peer computes something else than the template by design
(spheres instead of discs) is compared with the figure that design predicts, with the same
tolerance, and its difference from the template is shown.
"""
import json
import math
import os
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REL = 1e-9
CENTRE = 1e-9
F32 = 2.0 ** -24  # relative rounding of a float read by std::stof


def fail(msg):
    print("peer-check: " + msg, file=sys.stderr)
    sys.exit(2)


def ours(t):
    """The clump's figures from the template's discs (as the exports state them)."""
    d = t["discs"]
    m = sum(x["m"] for x in d)
    cx = sum(x["m"] * x["x"] for x in d) / m
    cy = sum(x["m"] * x["y"] for x in d) / m

    def izz(k):
        return sum(x["m"] * (k * x["r"] ** 2 + (x["x"] - cx) ** 2 + (x["y"] - cy) ** 2) for x in d)

    # YADE default: spheres of the grain's density, 0.4 m r^2, about their own mass centre.
    rho = t["density"]
    ms = [rho * 4.0 / 3.0 * math.pi * x["r"] ** 3 for x in d]
    ms_tot = sum(ms)
    sx = sum(mi * x["x"] for mi, x in zip(ms, d)) / ms_tot
    sy = sum(mi * x["y"] for mi, x in zip(ms, d)) / ms_tot
    i_def = sum(
        mi * (0.4 * x["r"] ** 2 + (x["x"] - sx) ** 2 + (x["y"] - sy) ** 2) for mi, x in zip(ms, d)
    )
    return {
        "mass": m,
        "cx": cx,
        "cy": cy,
        "izz": izz(0.5),
        "izz_spheres": izz(0.4),
        "default": {"mass": ms_tot, "cx": sx, "cy": sy, "izz": i_def},
    }


def quat_z_moment(moments, q):
    """The principal moment whose axis the body quaternion q = (w, i, j, k) turns onto z."""
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    # Third row of the rotation matrix: the z components of the rotated body axes.
    row = [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]
    k = max(range(3), key=lambda i: abs(row[i]))
    if abs(abs(row[k]) - 1) > 1e-9:
        fail("LAMMPS body has no principal axis along z (%r)" % (row,))
    return moments[k]


def lammps(infile, variables):
    cmd = ["lmp", "-in", os.path.join(HERE, infile), "-log", "none"]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    lines = p.stdout.splitlines()
    if p.returncode != 0 or not any(l.split()[:1] == ["Step"] for l in lines):
        fail("lmp %s failed (exit %d):\n%s" % (infile, p.returncode, "\n".join(lines[-15:])))
    head = next(i for i, l in enumerate(lines) if l.split()[:1] == ["Step"])
    data = []
    for l in lines[head + 1 :]:
        if l.startswith("Loop time"):
            break
        data.append([float(v) for v in l.split()])
    v = data[-1]
    moments, quat = v[5:8], v[8:12]
    return {"atoms": int(v[1]), "mass": v[2], "cx": v[3], "cy": v[4], "izz": quat_z_moment(moments, quat)}


def run_lammps(tpl_path, t, rows):
    mol = tpl_path[: -len(".json")] + ".lammps.mol"
    ext = max(math.hypot(x["x"], x["y"]) + x["r"] for x in t["discs"])
    gx = sum(x["x"] for x in t["discs"]) / len(t["discs"])
    gy = sum(x["y"] for x in t["discs"]) / len(t["discs"])
    common = {"mol": mol, "half": repr(20 * ext), "cut": repr(4 * ext)}
    a = lammps("lammps-atoms.in", dict(common, gx=repr(gx), gy=repr(gy)))
    rows.append(("lammps: atoms", a, "spheres"))
    with tempfile.TemporaryDirectory() as d:
        dump = os.path.join(d, "atoms.txt")
        b = lammps("lammps-deposit.in", dict(common, dump=dump))
        # Mass centre of the inserted atoms (LAMMPS puts the body anywhere in the box): the
        # body's centre must be theirs; shift both back to the template frame by the first atom.
        with open(dump) as f:
            atoms = [l.split() for l in f.read().split("ITEM: ATOMS id mass x y\n")[-1].splitlines()]
        atoms = sorted(([int(a[0])] + [float(v) for v in a[1:]] for a in atoms), key=lambda a: a[0])
    m = sum(a[1] for a in atoms)
    ax = sum(a[1] * a[2] for a in atoms) / m
    ay = sum(a[1] * a[3] for a in atoms) / m
    # The body's centre relative to the atoms' (0 when the header's com matches the atoms).
    b["cx"] -= ax
    b["cy"] -= ay
    b["relative_centre"] = True
    rows.append(("lammps: deposit", b, "exact"))


def run_yade(paths):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "yade.jsonl")
        env = dict(os.environ, PEER_YADE_FILES=":".join(paths), PEER_YADE_OUT=out)
        p = subprocess.run(
            ["yade", "-n", "-x", os.path.join(HERE, "yade_check.py")],
            capture_output=True,
            text=True,
            env=env,
        )
        if p.returncode != 0 or not os.path.exists(out):
            fail("yade failed (exit %d):\n%s" % (p.returncode, (p.stdout + p.stderr)[-2000:]))
        with open(out) as f:
            return [json.loads(l) for l in f]


def files(tpl_path, t, rows):
    stem = tpl_path[: -len(".json")]
    rho = t["density"]
    with open(stem + ".pfc.p2dat") as f:
        words = {}
        for line in f:
            line = line.split(";")[0].replace("...", " ").split()
            if line and line[0] in ("volume", "inertia", "position"):
                words[line[0]] = [float(v) for v in line[1:]]
    rows.append(
        (
            "pfc: file",
            {
                "mass": words["volume"][0] * rho,
                "cx": words["position"][0],
                "cy": words["position"][1],
                "izz": words["inertia"][2] * rho,
            },
            "exact",
        )
    )

    def f32(s):
        return struct.unpack("f", struct.pack("f", float(s)))[0]

    with open(stem + ".mercury/Inertia/Mass.txt") as f:
        mass = f32(f.read().strip())
    with open(stem + ".mercury/Inertia/TOI.txt") as f:
        toi = [[f32(v) for v in l.split(",")] for l in f.read().split()]
    with open(stem + ".mercury/Clump/Clump.txt") as f:
        peb = [[f32(v) for v in l.split(",")] for l in f.read().split()]
    # Pebbles are about the mass centre (principal frame): with the template's masses their
    # centre must be the origin.
    ms = [x["m"] for x in t["discs"]]
    cx = sum(m * p[0] for m, p in zip(ms, peb)) / sum(ms)
    cy = sum(m * p[1] for m, p in zip(ms, peb)) / sum(ms)
    rows.append(
        (
            "mercury: file (stof)",
            {"mass": mass, "cx": cx, "cy": cy, "izz": toi[2][2], "relative_centre": True},
            "float32",
        )
    )


def main(argv):
    paths = [p for p in argv if p.endswith(".json") and os.path.basename(p) != "summary.json"]
    if not paths:
        fail("usage: peer_check.py TEMPLATE.json...")
    t0 = time.time()
    templates = {}
    for p in paths:
        with open(p) as f:
            templates[p] = json.load(f)
    yade_rows = run_yade([p[: -len(".json")] + ".yade.py" for p in paths])
    print(
        "%-14s %-21s %-12s %-10s %-10s %-12s %-11s %-22s %s"
        % ("grain", "peer: path", "mass (kg)", "dm/m", "|dc|/Req", "I_z (kg m2)", "dI/I", "expected", "ok")
    )
    bad = 0
    for p in paths:
        t = templates[p]
        o = ours(t)
        grain = os.path.basename(p)[: -len(".json")]
        rows = [("ours (" + t["method"] + ")", o, "template")]
        for r in yade_rows:
            if r["grain"] == grain:
                rows.append(("yade: " + r["path"], r, {"export": "exact", "native": "spheres", "default": "default"}[r["path"]]))
        run_lammps(p, t, rows)
        files(p, t, rows)
        req = t["shape"]["r_eq"]
        for name, v, expect in rows:
            # What the peer should compute by design, and whether it does.
            want = dict(o)
            tol_m, tol_i = REL, REL
            if expect == "spheres":
                want["izz"] = o["izz_spheres"]
            elif expect == "default":
                want = o["default"]
            elif expect == "float32":
                tol_m, tol_i = 1.01 * F32, 2.02 * F32
            centre = (0.0, 0.0) if v.get("relative_centre") else (want["cx"], want["cy"])
            dc = math.hypot(v["cx"] - centre[0], v["cy"] - centre[1]) / req
            if expect == "float32":
                dc_ok = dc <= 1e-6  # pebble coordinates in single precision
            else:
                dc_ok = dc <= CENTRE
            ok = (
                abs(v["mass"] - want["mass"]) <= tol_m * want["mass"]
                and abs(v["izz"] - want["izz"]) <= tol_i * want["izz"]
                and dc_ok
            )
            bad += not ok
            label = {
                "template": "template (achieved)",
                "exact": "= ours",
                "spheres": "spheres: -sum .1mr^2",
                "default": "rho 4/3 pi r^3 spheres",
                "float32": "= ours to float32",
            }[expect]
            print(
                "%-14s %-21s %-12.6e %-+10.2e %-10.1e %-12.6e %-+11.3e %-22s %s"
                % (
                    grain[:14],
                    name,
                    v["mass"],
                    (v["mass"] - o["mass"]) / o["mass"],
                    dc,
                    v["izz"],
                    (v["izz"] - o["izz"]) / o["izz"],
                    label,
                    "ok" if ok else "MISMATCH",
                )
            )
        # The template's own figures agree with its discs (so "ours" is the template).
        a = t["achieved"]
        if abs(a["mass"] - o["mass"]) > REL * o["mass"] or abs(a["inertia_own"] - o["izz"]) > REL * o["izz"]:
            print("%s: template 'achieved' differs from its discs" % grain)
            bad += 1
    dt = time.time() - t0
    print("%d grains, %d mismatches, %.1f s (peers)" % (len(paths), bad, dt))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
