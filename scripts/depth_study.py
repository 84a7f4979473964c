#!/usr/bin/env python3
"""Tables and a plot of the depth study (issue 47 item 4; docs/cutting.md, "Depth trend")
from its committed runs.

Usage: scripts/depth_study.py DIR [--plot OUT.png] [--kic MPa_sqrt_m --ucs MPa]

DIR holds one folder per cut as written by scripts/depth-runs.sh:
  dD-sN            a_p = D mm, L 10 mm, Table 2's discs (r 0.175-0.285 mm), seed N
  l5-dD-sN         a_p = D mm, L 5 mm, the same discs
  fine-l5-dD-sN    a_p = D mm, L 5 mm, discs 2x finer (r 0.0875-0.1425 mm)
(The L 5 mm, a_p 1 mm coarse cuts are the damping-frame study's frag-lab-sN; pass that folder
with --coarse-l5-d1 DIR2.) Each cutting.result.json gives the window-mean main force (window
[2 a_p, L]) and the removal mode. The exponent m of F ~ a_p^m is the least-squares slope of
ln F on ln a_p over the depths' seed means (all depths, and those below and above the model's
length l = (K_IC/sigma_c)^2, Huang & Detournay 2008), and per seed.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cut_runs import kn, load, mean_se, slope, touching  # noqa: E402


def fmt(m, se, k=2):
    if math.isnan(m):
        return "–"
    return f"{m:.{k}f}" if math.isnan(se) else f"{m:.{k}f} ± {se:.{k}f}"


def main():
    a = sys.argv[1:]
    if not a:
        sys.exit(__doc__)
    d = a[0]
    opt = lambda k, dflt=None: a[a.index(k) + 1] if k in a else dflt
    plot = opt("--plot")
    kic = float(opt("--kic", "21.31"))  # MPa m^0.5: the model's SENB (calibration README)
    ucs = float(opt("--ucs", "822.9"))  # MPa: the model's UCS (calibration si3n4.md)
    ell = (kic / ucs) ** 2 * 1e3  # mm
    runs = load(d)
    extra = load(opt("--coarse-l5-d1"))
    depths = sorted({float(n.split("-s")[0][1:]) for n in runs if n.startswith("d")})
    seeds = sorted({int(n.rsplit("-s", 1)[1]) for n in runs})
    print(f"The model's length l = (K_IC/σ_c)² = ({kic:g} MPa·m^½ / {ucs:g} MPa)² = {ell:.3f} mm.\n")
    print("### Window-mean main force (kN) against depth, v 1 m/s, L 10 mm, fragment-frame damping\n")
    print("| seed | " + " | ".join(f"a_p {x:g} mm" for x in depths) + " | m (all depths) |")
    print("|---|" + "---|" * (len(depths) + 1))
    per_seed_m = []
    for s in seeds:
        row, xs, ys = [], [], []
        for x in depths:
            r = runs.get(f"d{x:g}-s{s}")
            if r is None:
                row.append("–")
            else:
                row.append(f"{kn(r):.2f}")
                if kn(r) > 0:
                    xs.append(x)
                    ys.append(kn(r))
        m = slope(xs, ys) if len(xs) == len(depths) else float("nan")
        if not math.isnan(m):
            per_seed_m.append(m)
        print(f"| {s} | " + " | ".join(row) + f" | {fmt(m, float('nan'))} |")
    means = []
    for x in depths:
        v = [kn(runs[f"d{x:g}-s{s}"]) for s in seeds if f"d{x:g}-s{s}" in runs]
        means.append((x, *mean_se(v), len(v)))
    cells = [f"{fmt(m, se)} ({n})" for _, m, se, n in means]
    ok = [(x, m) for x, m, _, n in means if n and m > 0]
    m_all = slope([x for x, _ in ok], [m for _, m in ok])
    pm, pse = mean_se(per_seed_m)
    print(f"| mean ± SE (seeds) | " + " | ".join(cells)
          + f" | {fmt(m_all, float('nan'))} (of the means); {fmt(pm, pse)} ({len(per_seed_m)} seeds) |")
    lo = [(x, m) for x, m in ok if x <= ell]
    hi = [(x, m) for x, m in ok if x >= ell]
    print(f"\nExponent of the means: below l ({', '.join(f'{x:g}' for x, _ in lo)} mm) "
          f"{fmt(slope(*zip(*lo)) if len(lo) > 1 else float('nan'), float('nan'))}; above l "
          f"({', '.join(f'{x:g}' for x, _ in hi)} mm) "
          f"{fmt(slope(*zip(*hi)) if len(hi) > 1 else float('nan'), float('nan'))}. "
          "Huang & Detournay: 1 (ductile) below l, 0.5 (brittle) above.\n")
    print("### Removal mode per depth (seed means)\n")
    print("| a_p (mm) | runs | tool touching (% of the window) | chip discs | single-grain share | largest chip (grains) | chip speed (m/s) | broken bonds | peak / mean |")
    print("|---|---|---|---|---|---|---|---|---|")
    for x in depths:
        rs = [runs[f"d{x:g}-s{s}"] for s in seeds if f"d{x:g}-s{s}" in runs]
        if not rs:
            continue
        g = lambda f: mean_se([f(r) for r in rs])[0]
        rm = lambda k: g(lambda r: (r.get("removal") or {}).get(k, float("nan")))
        pk = g(lambda r: r["main_force"]["peak"] / max(r["main_force"]["mean"], 1e-9))
        tw = [touching(d, f"d{x:g}-s{s}", runs[f"d{x:g}-s{s}"]) for s in seeds
              if f"d{x:g}-s{s}" in runs]
        tw = mean_se([t for t in tw if t is not None])[0]
        print(f"| {x:g} | {len(rs)} | {100 * tw:.0f} % | {rm('chip_discs'):.0f} | {100 * rm('single_grain_share'):.0f} % | "
              f"{rm('largest_chip_grains'):.0f} | {rm('chip_speed_mean'):.1f} | "
              f"{g(lambda r: r['broken_total']):.0f} | {pk:.0f} |")
    print("\n### Resolution: Table 2's discs against discs 2× finer, L 5 mm (kN)\n")
    print("| a_p (mm) | seed | r 0.175–0.285 mm | r 0.0875–0.1425 mm | fine / coarse | discs coarse / fine |")
    print("|---|---|---|---|---|---|")
    for x in (0.5, 1.0):
        for s in seeds:
            c = runs.get(f"l5-d{x:g}-s{s}") or (extra.get(f"frag-lab-s{s}") if x == 1.0 else None)
            f = runs.get(f"fine-l5-d{x:g}-s{s}")
            if c is None or f is None:
                continue
            ratio = kn(f) / kn(c) if kn(c) > 0 else float("nan")
            print(f"| {x:g} | {s} | {kn(c):.2f} | {kn(f):.2f} | {ratio:.2f} | {c['discs']} / {f['discs']} |")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.6))
        for s in seeds:
            pts = [(x, kn(runs[f"d{x:g}-s{s}"])) for x in depths if f"d{x:g}-s{s}" in runs]
            pts = [(x, y) for x, y in pts if y > 0]
            if pts:
                ax.plot(*zip(*pts), "o", color="0.6", ms=4, label=f"each seed ({len(seeds)})" if s == seeds[0] else None)
        mx = [x for x, m, _, n in means if n and m > 0]
        my = [m for x, m, _, n in means if n and m > 0]
        me = [se if not math.isnan(se) else 0 for x, m, se, n in means if n and m > 0]
        ax.errorbar(mx, my, yerr=me, fmt="s-", color="C0", capsize=3, label="seed mean ± SE")
        if my:
            x0, y0 = mx[len(mx) // 2], my[len(my) // 2]
            xs = [min(mx), max(mx)]
            ax.plot(xs, [y0 * (x / x0) for x in xs], "--", color="C1", label="∝ a_p (ductile)")
            ax.plot(xs, [y0 * (x / x0) ** 0.5 for x in xs], ":", color="C2", label="∝ √a_p (brittle)")
        ax.axvline(ell, color="C3", lw=1)
        ax.text(ell, ax.get_ylim()[1] * 0.8, f" l = (K_IC/σ_c)² = {ell:.2f} mm", color="C3", fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        import matplotlib.ticker

        ax.set_xticks(depths)
        ax.set_xticklabels([f"{x:g}" for x in depths])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("depth of cut a_p (mm)")
        ax.set_ylabel("window-mean main force (kN, t = 1 m)")
        ax.set_title("Si3N4, traditional, v 1 m/s, L 10 mm, fragment-frame damping", fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(plot, dpi=120)


if __name__ == "__main__":
    main()
