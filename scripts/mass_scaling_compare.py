#!/usr/bin/env python3
"""Mass-scaled against unscaled improved-ORC Table 2 cuts of the same specimens (docs/cutting.md,
"Mass scaling"): per cell, the window mean (paired seed differences, mean ± SE) and the
seed-averaged peak (w = a_p, with jackknife SEs), step and CPU ratios, what the scaling added.

    python3 scripts/mass_scaling_compare.py SCALED_DIR UNSCALED_DIR [--seeds 1-5]

Both folders hold run folders named <method>-d<a_p mm>-v<v>-s<seed> with cutting.result.json and
cutting.forces.csv (validation's table2-runs; a sweep's cases linked under those names). The
seed-averaged peak is dem_lab::force_stats::seed_averaged_peak written again (area-
preserving resampling on a 1 µm grid, seed average, moving mean over w): on the committed
10-seed improved a_p 1 mm, 1 m/s cell it gives peak/mean 1.4810, as the report's table2.json.
Standard library only; prints markdown.
"""
import bisect, json, math, os, sys


def load(d):
    r = json.load(open(os.path.join(d, "cutting.result.json")))
    s, f = [], []
    with open(os.path.join(d, "cutting.forces.csv")) as fh:
        next(fh)
        for line in fh:
            a = line.split(",")
            s.append(float(a[0]))
            f.append(float(a[2]))
    return r, s, f


def resample(s, f, lo, step, cells):
    cum = [0.0]
    for k in range(len(s) - 1):
        cum.append(cum[-1] + 0.5 * (s[k + 1] - s[k]) * (f[k] + f[k + 1]))

    def integral(x):
        k = bisect.bisect_right(s, x) - 1
        if k < 0:
            return 0.0
        if k + 1 >= len(s):
            return cum[-1]
        t = (x - s[k]) / (s[k + 1] - s[k])
        fx = f[k] + t * (f[k + 1] - f[k])
        return cum[k] + 0.5 * (x - s[k]) * (f[k] + fx)

    e = [integral(lo + j * step) for j in range(cells + 1)]
    return [(e[j + 1] - e[j]) / step for j in range(cells)]


def peak(runs, width, step=1e-6):
    w = runs[0][0]["window"]
    lo = max([w[0]] + [s[0] for _, s, _ in runs])
    hi = min([w[1]] + [s[-1] for _, s, _ in runs])
    cells = int(math.floor((hi - lo) / step * (1 + 1e-12)))
    avg = [0.0] * cells
    for _, s, f in runs:
        for j, v in enumerate(resample(s, f, lo, step, cells)):
            avg[j] += v / len(runs)
    n = max(1, round(width / step))
    p = [0.0]
    for x in avg:
        p.append(p[-1] + x)
    return max((p[j + n] - p[j]) / n for j in range(cells - n + 1))


def jackknife(runs, width):
    n = len(runs)
    th = [peak(runs[:i] + runs[i + 1:], width) for i in range(n)]
    m = sum(th) / n
    return math.sqrt((n - 1) / n * sum((t - m) ** 2 for t in th))


def mean_se(v):
    n = len(v)
    m = sum(v) / n
    return m, (math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1) / n) if n > 1 else 0.0)


def main():
    args = sys.argv[1:]
    seeds = range(1, 6)
    if "--seeds" in args:
        i = args.index("--seeds")
        a, b = args[i + 1].split("-")
        seeds = range(int(a), int(b) + 1)
        del args[i : i + 2]
    scaled, unscaled = args
    print("| cell | seeds | window mean, scaled / unscaled (kN) | paired difference (kN) | "
          "seed-averaged peak, scaled / unscaled (kN) | difference (kN) | steps ratio | "
          "CPU ratio | added mass | added spin inertia |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for cell in ["improved-d1-v1", "improved-d1-v2", "improved-d2-v1", "improved-d2-v2"]:
        pairs = []
        for s in seeds:
            a, b = (os.path.join(d, f"{cell}-s{s}") for d in (scaled, unscaled))
            if all(os.path.exists(os.path.join(x, "cutting.result.json")) for x in (a, b)):
                pairs.append((load(a), load(b), b))
        if not pairs:
            continue
        depth = float(cell.split("-")[1][1:]) * 1e-3
        ma, sa = mean_se([p[0][0]["main_force"]["mean"] for p in pairs])
        mb, sb = mean_se([p[1][0]["main_force"]["mean"] for p in pairs])
        dm, ds = mean_se([p[0][0]["main_force"]["mean"] - p[1][0]["main_force"]["mean"]
                          for p in pairs])
        ra, rb = [p[0] for p in pairs], [p[1] for p in pairs]
        pa, pb = peak(ra, depth), peak(rb, depth)
        ja, jb = (jackknife(ra, depth), jackknife(rb, depth)) if len(pairs) > 1 else (0, 0)
        se = math.hypot(ja, jb)
        steps = sum(p[1][0]["run"]["steps"] for p in pairs) / sum(p[0][0]["run"]["steps"]
                                                                  for p in pairs)
        cpu_b = []
        for p in pairs:
            t = os.path.join(p[2], "run.time.json")
            c = p[1][0]["run"].get("cpu_time_s")
            cpu_b.append(json.load(open(t))["cpu_time_s"] if os.path.exists(t) else c)
        cpu = sum(cpu_b) / sum(p[0][0]["run"]["cpu_time_s"] for p in pairs)
        ms = [p[0][0]["run"]["mass_scaling"] for p in pairs]
        am = [m["added_mass_fraction"] * 100 for m in ms]
        ai = [m["added_inertia_fraction"] * 100 for m in ms]
        def verdict(d, e):
            if len(pairs) < 2:
                return "one seed: no SE"
            return "within 2 SE" if abs(d) <= 2 * e else "**beyond 2 SE**"

        print(f"| {cell} | {len(pairs)} | {ma/1e3:.1f} ± {sa/1e3:.1f} / {mb/1e3:.1f} ± {sb/1e3:.1f} "
              f"| {dm/1e3:+.1f} ± {ds/1e3:.1f} ({verdict(dm, ds)}) "
              f"| {pa/1e3:.1f} ± {ja/1e3:.1f} / {pb/1e3:.1f} ± {jb/1e3:.1f} "
              f"| {(pa-pb)/1e3:+.1f} ± {se/1e3:.1f} ({verdict(pa - pb, se)}) "
              f"| {steps:.2f} | {cpu:.2f} | {min(am):.2f}–{max(am):.2f} % "
              f"| {min(ai):.2f}–{max(ai):.2f} % |")
    print()
    print("Forces for t = 1 m; ± one standard error (paired differences; jackknife for peaks). "
          "Ratios: unscaled / scaled, summed over the seeds.")


if __name__ == "__main__":
    main()
