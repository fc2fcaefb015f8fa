#!/usr/bin/python3
"""What the ray caster's budget would cost with its factors at the user's step (docs/budget.md, "Why not a coarser
baseline"): not what `uvr budget` runs, a measurement for the spec's owner.

    PYTHONPATH=build/python /usr/bin/python3 bench/budget_at_user_step.py [VOLUME] [--rounds 5]

In one process (the scene read once, the reference from the cache, filled first): the step's run (every other switch
exact at the user's step), the table, texture and interpolation factors at the user's step, termination likewise
unless no ray of the step's run passes the threshold (then it is that run, as `uvr budget` copies it), and the default
configuration. Against the default frame's whole `uvr render` process, in alternating rounds; the median of the
per-round ratios is reported, with each run's RMSE against the reference and against the step's run.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import uvr

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.path.join(HERE, "build", "bench", "uvr")
EXACT = dict(segment="exact", volume_format="f32", interpolation="exact", threshold="1", preintegrate=True)
THRESHOLD = 0.95  # the ray caster's default early termination


def rmse(a, b):
    return float(np.sqrt(np.mean((a.astype(float) - b.astype(float)) ** 2)))


def budget_at_step(volume, size):
    t0 = time.perf_counter()
    scene = uvr.Scene(volume, size=(size, size))
    reference = uvr.render(scene, "reference")
    step = uvr.render(scene, "raycast", **EXACT)
    runs = {"step": step,
            "table": uvr.render(scene, "raycast", **{**EXACT, "segment": "table", "preintegrate": False}),
            "texture": uvr.render(scene, "raycast", **{**EXACT, "volume_format": "native"}),
            "interpolation": uvr.render(scene, "raycast", **{**EXACT, "interpolation": "gpu"})}
    runs["termination"] = (step if step[..., 3].max() <= np.float32(THRESHOLD)
                           else uvr.render(scene, "raycast", **{**EXACT, "threshold": str(THRESHOLD)}))
    runs["total"] = uvr.render(scene, "raycast")
    return time.perf_counter() - t0, runs, reference


def frame(volume, size, out):
    t0 = time.perf_counter()
    subprocess.run([PROGRAM, "render", volume, "--algo", "raycast", "--size", f"{size}x{size}", "--out", out],
                   check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("volume", nargs="?", default=os.path.join(HERE, "data", "vtk-data", "neghip.slc"))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--size", type=int, default=512)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "frame.npy")
        subprocess.run([PROGRAM, "render", a.volume, "--algo", "reference", "--size", f"{a.size}x{a.size}", "--out",
                        out], check=True, stdout=subprocess.DEVNULL)  # fills the cache
        ratios = []
        for r in range(a.rounds):
            if r % 2:
                f = frame(a.volume, a.size, out)
                b, runs, reference = budget_at_step(a.volume, a.size)
            else:
                b, runs, reference = budget_at_step(a.volume, a.size)
                f = frame(a.volume, a.size, out)
            ratios.append(b / f)
            print(f"round {r + 1}: the runs in one process {b:.3f} s, the default frame's process {f:.3f} s, "
                  f"{b / f:.2f} frames")
    print(f"median: {statistics.median(ratios):.2f} frames")
    for name, image in runs.items():
        print(f"  {name}: RMSE {rmse(image, reference):.2e} against the reference, "
              f"{rmse(image, runs['step']):.2e} against the step's run")


if __name__ == "__main__":
    sys.exit(main())
