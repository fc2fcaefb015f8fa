#!/usr/bin/python3
"""Measure images against uvr's reference the one way uvr measures an outside image: `uvr compare --image`.

    measure_images.py --uvr build/bench/uvr --report DIR [--colour-only] --image LABEL=FILE ... -- SCENE [options]

Runs `uvr compare SCENE [options] --algos reference --image FILE --label LABEL ... --report DIR --json` and prints its
metrics.json object (docs/spec.md §4's measures per label, and covered_left_empty). With --colour-only, an image that has
alpha (uvr's own .npy) is first cut to its colour (H x W x 3, written under DIR-colour/), so that it is measured as
the peers' 8-bit RGB images are: on the colour over black.
"""
import argparse
import os
import subprocess
import sys

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--uvr", required=True)
    ap.add_argument("--report", required=True)
    ap.add_argument("--colour-only", action="store_true")
    ap.add_argument("--image", action="append", default=[], help="LABEL=FILE")
    ap.add_argument("scene", nargs=argparse.REMAINDER, help="-- then the scene and its options")
    a = ap.parse_args()
    scene = a.scene[1:] if a.scene[:1] == ["--"] else a.scene
    args = [a.uvr, "compare", *scene, "--algos", "reference", "--report", a.report, "--json"]
    for item in a.image:
        label, _, path = item.partition("=")
        if a.colour_only and path.endswith(".npy"):
            image = np.load(path)
            if image.ndim == 3 and image.shape[2] == 4:
                os.makedirs(a.report + "-colour", exist_ok=True)
                path = f"{a.report}-colour/{label}.npy"
                np.save(path, np.ascontiguousarray(image[:, :, :3], dtype=np.float32))
        args += ["--image", path, "--label", label]
    done = subprocess.run(args, stdout=subprocess.PIPE)
    if done.returncode != 0:
        sys.exit(done.returncode)
    sys.stdout.write(done.stdout.decode())


if __name__ == "__main__":
    main()
