"""Helpers of the study scripts (damping_frame_study.py, depth_study.py): read a folder of
`dem test cutting` runs and the statistics their tables use."""
import json
import math
import os


def load(d):
    """{folder name: cutting.result.json} for every finished run in d (none if d is missing)."""
    out = {}
    if not d or not os.path.isdir(d):
        return out
    for name in sorted(os.listdir(d)):
        f = os.path.join(d, name, "cutting.result.json")
        if os.path.isfile(f):
            with open(f) as fh:
                out[name] = json.load(fh)
    return out


def mean_se(xs):
    """Mean and standard error (nan where undefined)."""
    n = len(xs)
    if n == 0:
        return float("nan"), float("nan")
    m = sum(xs) / n
    if n < 2:
        return m, float("nan")
    return m, math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n)


def slope(x, y):
    """Least-squares slope of ln y on ln x."""
    lx = [math.log(a) for a in x]
    ly = [math.log(b) for b in y]
    n = len(lx)
    if n < 2:
        return float("nan")
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx


def kn(r):
    """Window-mean main force (kN)."""
    return r["main_force"]["mean"] / 1e3


def touching(d, name, r):
    """Share of the window's force rows with the tool touching anything (main force > 0);
    None without the run's cutting.forces.csv."""
    f = os.path.join(d, name, "cutting.forces.csv")
    if r is None or not os.path.isfile(f):
        return None
    w0, w1 = r["window"]
    n = k = 0
    with open(f) as fh:
        next(fh)
        for line in fh:
            s, _, m, _ = line.split(",")
            if w0 <= float(s) <= w1:
                n += 1
                k += float(m) > 0
    return k / n if n else None
