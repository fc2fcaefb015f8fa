#!/usr/bin/python3
"""Tabulates and plots a `bench/scaling.sh` run (DIR/torus-*/bench-*.json): frame time and peak memory per tetrahedron
of each algorithm and backend against the tetrahedron count, with the least-squares slope of log(time) against
log(count) (1 means linear growth), over all sizes and over the three largest (where the per-pixel work, which does not
grow with the mesh, no longer dominates). Writes DIR/scaling.png and prints a Markdown table."""
import glob
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def main():
    d = sys.argv[1]
    runs = {}
    for f in sorted(glob.glob(f"{d}/torus-*/bench-*.json")):
        with open(f) as fh:
            b = json.load(fh)
        r = b["results"][0]
        if r["algo"] == "reference":
            name = "reference"
        elif r["algo"] == "vicp":
            name = f"VICP {r['order']} {r['backend']}"
        else:
            name = f"HAVS k={r['k']} {r['backend']}"
        runs.setdefault(name, []).append((b["tetrahedra"], r["frame_ms"], b["bytes_per_tet"], b["peak_rss_mib"]))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5), dpi=110)
    print("| path | tetrahedra | ms/frame | peak MiB | bytes per tetrahedron |")
    print("|---|---|---|---|---|")
    for name, pts in sorted(runs.items()):
        pts.sort()
        for n, ms, bpt, mib in pts:
            print(f"| {name} | {n:,} | {ms:.1f} | {mib:.0f} | {bpt:.0f} |")
        xs = [p[0] for p in pts]
        s_time = slope(xs, [p[1] for p in pts]) if len(pts) > 1 else float("nan")
        tail = pts[-3:]
        s_tail = slope([p[0] for p in tail], [p[1] for p in tail]) if len(tail) > 1 else float("nan")
        label = f"{name} (slope {s_time:.2f}; largest three {s_tail:.2f})" if len(pts) > 1 else name
        a1.plot(xs, [p[1] for p in pts], marker="o", label=label)
        a2.plot(xs, [p[2] for p in pts], marker="o", label=name)
        print(f"| {name}: slope of log(time) against log(count), all sizes / largest three | {s_time:.2f} / "
              f"{s_tail:.2f} | | | |")
    for a in (a1, a2):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("tetrahedra")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    a1.set_ylabel("ms per frame (512 x 512)")
    a1.set_title("Frame time against mesh size")
    a2.set_ylabel("peak memory per tetrahedron (bytes)")
    a2.set_title("Memory against mesh size")
    fig.tight_layout()
    fig.savefig(f"{d}/scaling.png")


if __name__ == "__main__":
    main()
