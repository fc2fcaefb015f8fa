#!/usr/bin/python3
"""The plot of a `uvr verify` report (DIR/verify.json) with matplotlib (Debian's python3-matplotlib): each measure's
error against h in log-log, the least-squares line through it (its slope is the observed order), and a line of the
expected order through the coarsest level. Writes DIR/verify.png."""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    d = sys.argv[1]
    with open(f"{d}/verify.json") as f:
        v = json.load(f)
    h = v["h"]
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    for key, name, colour in (("rmse", "RMSE", "tab:blue"), ("max_abs", "largest error", "tab:orange")):
        m = v["measures"][key]
        e = m["errors"]
        x = h[:len(e)]  # successive differences have one level fewer than images
        ax.plot(x, e, "o-", color=colour, label=f"{name}: order {m['order']:.2f}")
        # The fitted line: log e = order log h + c through the levels' centroid.
        cx = sum(math.log(t) for t in x) / len(x)
        cy = sum(math.log(t) for t in e) / len(e)
        ax.plot(x, [math.exp(cy + m["order"] * (math.log(t) - cx)) for t in x], ":", color=colour, linewidth=1)
        expected = v["expected_order"][key] if v.get("expected_order") else None
        if expected is not None:
            ax.plot(x, [e[0] * (t / x[0]) ** expected for t in x], "--", color="0.5", linewidth=1,
                    label=f"expected order {expected:g} ({name})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.invert_xaxis()
    ax.set_xlabel("h (refined to the right)")
    ax.set_ylabel("error")
    verdict = v.get("verdict") or "no verdict"
    ax.set_title(f"uvr verify: {v.get('algo', 'images')} {v.get('refine', '')} ({verdict})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{d}/verify.png")


if __name__ == "__main__":
    main()
