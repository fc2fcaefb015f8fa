#!/usr/bin/python3
"""The chart of a `uvr budget` report (DIR/budget.json) with matplotlib (Debian's python3-matplotlib): each run's RMSE
(baseline, one bar per factor, total) on a logarithmic axis, the largest error as a marker; a factor measured against
the step run (the ray caster's, docs/spec.md §7) is labelled so. Writes DIR/budget.png."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    d = sys.argv[1]
    with open(f"{d}/budget.json") as f:
        b = json.load(f)
    names = ["baseline", *(f"{n}\n(vs step)" if b["factors"][n].get("against") == "step" else n
                           for n in b["factor_order"]), "total"]
    runs = [b["baseline"], *(b["factors"][n] for n in b["factor_order"]), b["total"]]
    floor = 1e-9  # an exact run (RMSE 0) drawn at the axis' floor
    rmse = [max(r["rmse"], floor) for r in runs]
    largest = [max(r["max_abs"], floor) for r in runs]
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=110)
    colours = ["0.6"] + ["tab:blue"] * (len(names) - 2) + ["tab:red"]
    ax.bar(names, rmse, color=colours, label="RMSE")
    ax.plot(names, largest, "k_", markersize=18, label="largest error")
    ax.set_yscale("log")
    ax.set_ylim(bottom=floor)
    ax.set_ylabel("error against the reference (or the step run)")
    ax.set_title(f"{b['algo']} error budget: {b['mesh']}")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{d}/budget.png")


if __name__ == "__main__":
    main()
