#!/usr/bin/env python3
"""Tables and a plot of the damping-frame study (issue 47; docs/cutting.md, "Damping and the
frame of reference") from its committed runs.

Usage: scripts/damping_frame_study.py DIR [--plot OUT.png]

DIR holds one folder per cut, named `<damping>-<case>-s<seed>` as written by the study's
commands (docs/report/studies/damping-frame/README.md):
  spec-sN / frag-lab-sN      lab frame, v = 1 m/s (PFC local damping / fragment frame)
  lab-tool-sN / frag-tool-sN the same cut run in the tool's frame (`--frame tool`)
  lab-vV-sN / frag-vV-sN     other speeds V (m/s)
Each folder's cutting.result.json gives the window-mean main force. Prints Markdown tables:
the frame test (paired lab − tool difference per damping, mean ± SE over seeds), and the
forces against speed with the exponent n of F ∝ v^n (least squares on ln F – ln v over the
speeds whose seed-mean force is positive; per seed where all its forces are positive).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cut_runs import kn, load, mean_se, slope  # noqa: E402
from cut_runs import touching as touching_of  # noqa: E402


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    d = args[0]
    plot = args[args.index("--plot") + 1] if "--plot" in args else None
    runs = load(d)
    seeds = sorted({int(n.rsplit("-s", 1)[1]) for n in runs})

    def name_of(damping, case, s):
        if damping == "fragc":
            return f"fragc-v{case}-s{s}"
        if damping == "lab" and case == "lab":
            return f"spec-s{s}"
        if case in ("lab", "tool"):
            return f"{'lab' if damping == 'lab' else 'frag'}-{case}-s{s}"
        if case == "1":
            return name_of(damping, "lab", s)
        return f"{'lab' if damping == 'lab' else 'frag'}-v{case}-s{s}"

    def touching(damping, case, s):
        name = name_of(damping, case, s)
        return touching_of(d, name, runs.get(name))

    def at(damping, case, s):
        if damping == "fragc":
            return runs.get(name_of(damping, case, s))
        if damping == "lab" and case == "lab":
            name = f"spec-s{s}"
        elif case in ("lab", "tool"):
            name = f"{'lab' if damping == 'lab' else 'frag'}-{case}-s{s}"
        else:
            name = f"{'lab' if damping == 'lab' else 'frag'}-v{case}-s{s}"
            if case == "1":
                return at(damping, "lab", s)
        r = runs.get(name)
        return None if r is None else r

    print("### Frame test: window-mean main force (kN), a_p 1 mm, v 1 m/s, L 5 mm\n")
    print("| seed | PFC local, lab frame | PFC local, tool frame | fragment, lab frame | fragment, tool frame |")
    print("|---|---|---|---|---|")
    diffs = {"lab": [], "fragment": []}
    for s in seeds:
        cells = []
        for dmp in ("lab", "fragment"):
            a, b = at(dmp, "lab", s), at(dmp, "tool", s)
            cells += ["–" if a is None else f"{kn(a):.2f}", "–" if b is None else f"{kn(b):.2f}"]
            if a is not None and b is not None:
                diffs[dmp].append(kn(a) - kn(b))
        if any(c != "–" for c in cells):
            print(f"| {s} | " + " | ".join(cells) + " |")
    for dmp, label in (("lab", "PFC local damping"), ("fragment", "fragment frame")):
        m, se = mean_se(diffs[dmp])
        n = len(diffs[dmp])
        pos = sum(1 for x in diffs[dmp] if x > 0)
        print(f"\n{label}: lab − tool frame {m:+.2f} ± {se:.2f} kN (mean ± SE over {n} seeds; "
              f"lab frame higher in {pos} of {n})")

    print("\n### Where the tool's work goes (lab frame, v 1 m/s; % of the boundary work, seed means)\n")
    print("| damping | boundary work (J) | local damping | friction | bond breakage | kinetic at the end | single-grain share of chip discs | chip speed mean (m/s) |")
    print("|---|---|---|---|---|---|---|---|")
    for dmp, label in (("lab", "PFC local"), ("fragment", "fragment frame")):
        rows = []
        for s in seeds:
            r = at(dmp, "lab", s)
            if r is None:
                continue
            sm = os.path.join(d, f"spec-s{s}" if dmp == "lab" else f"frag-lab-s{s}", "summary.json")
            if not os.path.isfile(sm):
                continue
            with open(sm) as fh:
                e = json.load(fh)["energy"]
            w = e["boundary_work"]
            ke = e["kinetic_translation"] + e["kinetic_rotation"]
            rm = r.get("removal") or {}
            rows.append([w, e["damping"] / w, e["friction"] / w, e["bond_break"] / w, ke / w,
                         rm.get("single_grain_share", float("nan")),
                         rm.get("chip_speed_mean", float("nan"))])
        if not rows:
            continue
        m = [sum(c) / len(c) for c in zip(*rows)]
        print(f"| {label} ({len(rows)} seeds) | {m[0]:.1f} | {100 * m[1]:.0f} % | {100 * m[2]:.0f} % | "
              f"{100 * m[3]:.0f} % | {100 * m[4]:.0f} % | {100 * m[5]:.0f} % | {m[6]:.1f} |")

    print("\n### Main force against speed (kN), traditional specimen, a_p 1 mm, L 5 mm\n")
    speeds = ["0.25", "0.5", "1", "2", "4"]
    series = {}
    dampings = (("lab", "PFC local (lab frame)"), ("fragment", "fragment frame"),
                ("fragc", "fragment frame + contact dashpots 0.2 (pilot)"))
    for dmp, label in dampings:
        if not any(at(dmp, v, s) for v in speeds for s in seeds):
            continue
        print(f"{label}:\n")
        print("| seed | " + " | ".join(f"v {v}" for v in speeds) + " | n | n (0.5–4 m/s) |")
        print("|---|" + "---|" * (len(speeds) + 2))
        ns = []
        per_v = {v: [] for v in speeds}
        for s in seeds:
            row, vs, fs = [], [], []
            for v in speeds:
                r = at(dmp, v, s)
                if r is None:
                    row.append("–")
                    continue
                f = kn(r)
                row.append(f"{f:.2f}")
                per_v[v].append(f)
                vs.append(float(v))
                fs.append(f)
            if all(c == "–" for c in row):
                continue
            n = (f"{slope(vs, fs):.2f}" if len(vs) >= 3 and all(f > 0 for f in fs)
                 else "–")
            hi = [(a, b) for a, b in zip(vs, fs) if a >= 0.5 and b > 0]
            n2 = "–"
            if len(hi) >= 3:
                k = slope([a for a, _ in hi], [b for _, b in hi])
                ns.append(k)
                n2 = f"{k:.2f} ({len(hi)} speeds)"
            print(f"| {s} | " + " | ".join(row) + f" | {n} | {n2} |")
        ms = {v: mean_se(per_v[v]) for v in speeds if per_v[v]}
        row = [f"{ms[v][0]:.2f} ± {ms[v][1]:.2f} ({len(per_v[v])})" if v in ms else "–"
               for v in speeds]
        good = [v for v in speeds if v in ms and ms[v][0] > 0]
        n = f"{slope([float(v) for v in good], [ms[v][0] for v in good]):.2f}" if len(good) >= 3 else "–"
        mn, se = mean_se(ns)
        n2 = f"{mn:.2f} ± {se:.2f} ({len(ns)} seeds)" if ns else "–"
        print("| mean ± SE (seeds) | " + " | ".join(row) + f" | {n} (of the means) | {n2} |\n")
        series[label] = ms
    print("### Tool touching anything: share of the window's force rows with main force > 0 "
          "(seed means; a_p 1 mm, L 5 mm)\n")
    print("| damping | frame | " + " | ".join(f"v {v}" for v in speeds) + " |")
    print("|---|---|" + "---|" * len(speeds))
    for dmp, label in dampings:
        for case, frame in (("v", "lab"), ("tool", "tool")):
            if case == "tool" and dmp == "fragc":
                continue
            cells = []
            for v in speeds:
                if case == "tool" and v != "1":
                    cells.append("–")
                    continue
                t = [x for x in (touching(dmp, "tool" if case == "tool" else v, s) for s in seeds)
                     if x is not None]
                cells.append(f"{100 * sum(t) / len(t):.0f} % ({len(t)})" if t else "–")
            if any(c != "–" for c in cells):
                print(f"| {label} | {frame} | " + " | ".join(cells) + " |")
    print()
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker

        fig, ax = plt.subplots(figsize=(6, 4.2))
        for (label, ms), mk in zip(series.items(), ("o-", "s--", "^:")):
            vs = [float(v) for v in speeds if v in ms and ms[v][0] > 0]
            m = [ms[v][0] for v in speeds if v in ms and ms[v][0] > 0]
            e = [0 if math.isnan(ms[v][1]) else ms[v][1] for v in speeds if v in ms and ms[v][0] > 0]
            ax.errorbar(vs, m, yerr=e, fmt=mk, capsize=3, label=label)
        vv = [0.25, 4.0]
        ax.plot(vv, [20 * (x / 1.0) for x in vv], ":", color="grey", label="∝ v (n = 1)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xticks([0.25, 0.5, 1, 2, 4])
        ax.set_xticklabels(["0.25", "0.5", "1", "2", "4"])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("cutting speed v (m/s)")
        ax.set_ylabel("window-mean main force (kN, t = 1 m)")
        ax.set_title("Traditional Si3N4, a_p 1 mm, L 5 mm: mean ± SE over the seeds run\n"
                     "(seeds per point in docs/cutting.md)", fontsize=9)
        ax.legend(fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        tmp = plot + ".tmp.png"
        fig.savefig(tmp, dpi=120)
        os.replace(tmp, plot)
        print(f"plot: {plot}")


if __name__ == "__main__":
    main()
