#!/usr/bin/python3
"""Plots of a `uvr sweep` report (DIR/sweep.json) with matplotlib (Debian's python3-matplotlib):
error against k per view and their mean, split into the sorting error (exact segments) and the total (table), and
the fraction of pixels with ordering errors against k. Writes DIR/error_vs_k.png and DIR/ordering_vs_k.png, and with
a table-size sweep (--table-sizes) DIR/table_error_vs_size.png: the table's error against exact integration at the
largest k, against the table size."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    d = sys.argv[1]
    with open(f"{d}/sweep.json") as f:
        sweep = json.load(f)
    rows = sweep["rows"]
    ks = sorted({r["k"] for r in rows})
    views = sorted({r["view"] for r in rows})

    def series(view, mode, key):
        pts = sorted((r["k"], r[key]) for r in rows if r["view"] == view and r["mode"] == mode)
        return [p[0] for p in pts], [p[1] for p in pts]

    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    for mode, style, name in (("exact", "-", "sorting (exact segments)"), ("table", "--", "total (table)")):
        for v in views:
            x, y = series(v, mode, "rmse")
            ax.plot(x, y, style, color="0.75", linewidth=0.8)
        mean = [sum(r["rmse"] for r in rows if r["k"] == k and r["mode"] == mode) /
                max(1, sum(1 for r in rows if r["k"] == k and r["mode"] == mode)) for k in ks]
        ax.plot(ks, mean, style, marker="o", linewidth=2, label=f"{name}, mean of {len(views)} views")
    if "table_floor_rmse" in sweep:
        ax.axhline(sweep["table_floor_rmse"], color="tab:red", linewidth=1, linestyle=":",
                   label="table error (table vs exact at the largest k)")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xticks(ks)
    ax.set_xticklabels([str(k) for k in ks])
    ax.set_xlabel("k (k-buffer entries)")
    ax.set_ylabel("RMSE against the reference")
    ax.set_title(f"HAVS error against k: {sweep['mesh']}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{d}/error_vs_k.png")

    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    for v in views:
        x, y = series(v, "exact", "ordering_error_pixel_fraction")
        ax.plot(x, y, marker="o", label=f"view {v}")
    ax.set_xscale("log", base=2)
    ax.set_xticks(ks)
    ax.set_xticklabels([str(k) for k in ks])
    ax.set_xlabel("k (k-buffer entries)")
    ax.set_ylabel("fraction of pixels with ordering errors")
    ax.set_title(f"HAVS ordering errors against k: {sweep['mesh']}")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{d}/ordering_vs_k.png")

    table_rows = sweep.get("table_rows", [])
    if table_rows:
        sizes = sorted({r["table_size"] for r in table_rows})
        fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
        for key, name in (("rmse", "RMSE"), ("max_abs", "largest error")):
            for v in views:
                pts = sorted((r["table_size"], r[key]) for r in table_rows if r["view"] == v)
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "-" if key == "rmse" else "--", marker="o",
                        label=f"{name}, view {v}")
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xticks(sizes)
        ax.set_xticklabels([str(n) for n in sizes])
        ax.set_xlabel("table size (texels per axis)")
        ax.set_ylabel(f"error against exact segments, k = {ks[-1]}")
        ax.set_title(f"Pre-integration table error against its size: {sweep['mesh']}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(f"{d}/table_error_vs_size.png")

    budget_rows = sweep.get("budget_rows", [])
    if budget_rows:
        # The budget against k (sweep --budget): each factor's RMSE, the mean over the views, and the total.
        names = list(budget_rows[0]["factors"].keys())
        fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
        floor = 1e-9  # an exact run drawn at the axis' floor
        for name in names + ["total"]:
            mean = []
            for k in ks:
                at = [r for r in budget_rows if r["k"] == k]
                vals = [(r["total"] if name == "total" else r["factors"][name]) for r in at]
                mean.append(max(sum(vals) / max(1, len(vals)), floor))
            ax.plot(ks, mean, "-" if name != "total" else "--", marker="o", linewidth=2 if name == "total" else 1.2,
                    label=name)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xticks(ks)
        ax.set_xticklabels([str(k) for k in ks])
        ax.set_xlabel("k (k-buffer entries)")
        ax.set_ylabel(f"RMSE against the reference, mean of {len(views)} views")
        ax.set_title(f"HAVS error budget against k: {sweep['mesh']}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(f"{d}/budget_vs_k.png")


if __name__ == "__main__":
    main()
