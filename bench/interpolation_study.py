#!/usr/bin/env python3
"""The paper's interpolation against uvr's exact one: HAVS with --interpolation gpu and exact.

    python3 bench/interpolation_study.py [--uvr build/bench/uvr] [--data data] [--out out/interpolation]
                                         [--sizes 512,1024,2048,4096] [--parts views,sizes]

Part 1, per mesh and view at 512^2, converged (exact segments, exact gaps, no early termination, k = 255, the
rasterizer's coverage): each mode against the reference, and the two modes against each other.
Part 2, the growth with image size (one view per mesh; the default table and k = 64, so that 4096^2 fits in memory):
the two modes against each other. llvmpipe interpolates relative to the framebuffer's origin, so a triangle's plane
is extrapolated over more pixels in a larger image.
Measures as docs/spec.md §4 (RMSE, largest channel error, visible fraction: largest channel error over 1/255). Writes
OUT/interpolation.csv and prints it. Needs python3-numpy (Debian).
"""
import argparse
import csv
import os
import subprocess
import sys

import numpy as np

MESHES = {
    "torus": ["builtin:torus"],
    "bluntfin": ["@vtk-data/bluntfinxyz.bin", "--q", "@vtk-data/bluntfinq.bin"],
    "oxygen-post": ["@vtk-data/postxyz.bin", "--q", "@vtk-data/postq.bin", "--field", "StagnationEnergy"],
}
VIEWS = [(0.0, 0.0), (35.0, 40.0), (-70.0, 15.0)]
CONVERGED = ["--segment", "exact", "--threshold", "1", "--k", "255"]
SWEEP = ["--k", "64"]


def measures(a, b):
    d = np.abs(a.astype(np.float64) - b.astype(np.float64))
    return {"rmse": float(np.sqrt((d ** 2).mean())), "max_abs": float(d.max()),
            "visible_fraction": float((d.max(axis=2) > 1.0 / 255.0).mean())}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--uvr", default="build/bench/uvr")
    ap.add_argument("--data", default="data")
    ap.add_argument("--out", default="out/interpolation")
    ap.add_argument("--sizes", default="512,1024,2048,4096")
    ap.add_argument("--parts", default="views,sizes", help="which parts to run: views, sizes or both")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    def render(mesh, extra, name):
        path = os.path.join(args.out, name + ".npy")
        cmd = [args.uvr, "render"] + [a.replace("@", args.data + "/") for a in MESHES[mesh]] + extra + ["--out", path]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        return np.load(path)

    rows = []
    parts = args.parts.split(",")
    for mesh in MESHES if "views" in parts else []:
        for az, el in VIEWS:
            scene = ["--size", "512x512", "--view", f"{az},{el}"]
            tag = f"{mesh}_{az:g}_{el:g}_512"
            ref = render(mesh, scene + ["--algo", "reference"], tag + "_reference")
            gpu = render(mesh, scene + ["--algo", "havs", "--interpolation", "gpu"] + CONVERGED, tag + "_gpu")
            exact = render(mesh, scene + ["--algo", "havs", "--interpolation", "exact"] + CONVERGED, tag + "_exact")
            for what, a, b in (("gpu-reference", gpu, ref), ("exact-reference", exact, ref), ("gpu-exact", gpu, exact)):
                rows.append({"part": "views", "mesh": mesh, "view": f"{az:g},{el:g}", "size": 512, "pair": what,
                             **measures(a, b)})
                print(rows[-1], flush=True)
    for mesh in MESHES if "sizes" in parts else []:
        for size in [int(s) for s in args.sizes.split(",")]:
            scene = ["--size", f"{size}x{size}", "--view", "35,40"]
            tag = f"{mesh}_35_40_{size}"
            gpu = render(mesh, scene + ["--algo", "havs", "--interpolation", "gpu"] + SWEEP, tag + "_gpu")
            exact = render(mesh, scene + ["--algo", "havs", "--interpolation", "exact"] + SWEEP, tag + "_exact")
            rows.append({"part": "sizes", "mesh": mesh, "view": "35,40", "size": size, "pair": "gpu-exact",
                         **measures(gpu, exact)})
            print(rows[-1], flush=True)
            for p in (tag + "_gpu.npy", tag + "_exact.npy"):
                os.remove(os.path.join(args.out, p))  # 256 MiB each at 4096^2
    with open(os.path.join(args.out, "interpolation.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
