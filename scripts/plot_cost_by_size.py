#!/usr/bin/python3
"""Frame time against scene size: the median and p99 of one technique from bench.json files of
the same path kind on scenes of different sizes (issue 16's flat-cost check: clusters'
median at 100M triangles against 1M), drawn on a log scale of triangles, and printed as a
table with each median's ratio to the smallest scene's.

    scripts/plot_cost_by_size.py --technique clusters --out cost.png b1m/bench.json b10m/bench.json b100m/bench.json

Needs python3-matplotlib (Debian), which `make deps` installs.
"""
import argparse
import json
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("reports", nargs="+", help="bench.json files")
    parser.add_argument("--technique", "-t", default="clusters", help="technique to plot")
    parser.add_argument("--out", "-o", required=True, help="PNG to write")
    args = parser.parse_args()

    rows = []
    for path in args.reports:
        try:
            with open(path) as f:
                report = json.load(f)
        except (OSError, ValueError) as e:
            sys.exit(f"plot_cost_by_size: {path}: {e}")
        found = [t for t in report.get("techniques", []) if t.get("name") == args.technique]
        if not found:
            names = ", ".join(t.get("name", "?") for t in report.get("techniques", []))
            sys.exit(f"plot_cost_by_size: {path}: no technique '{args.technique}' (it has {names})")
        summary = found[0]["summary"]
        rows.append((report["scene"]["triangles"], summary["median_ms"], summary["p99_ms"], path,
                     report.get("renderer", "?")))
    rows.sort()

    base = rows[0][1]
    print(f"{'triangles':>12} {'median_ms':>10} {'p99_ms':>10} {'x_smallest':>10}  report")
    for triangles, median, p99, path, _ in rows:
        print(f"{triangles:>12,} {median:>10.2f} {p99:>10.2f} {median / base:>10.2f}  {path}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    xs = [r[0] for r in rows]
    ax.plot(xs, [r[1] for r in rows], "o-", label="median")
    ax.plot(xs, [r[2] for r in rows], "s--", label="p99")
    ax.set_xscale("log")
    ax.set_xlabel("scene triangles")
    ax.set_ylabel("frame time, ms")
    ax.set_ylim(bottom=0)
    ax.set_title(f"{args.technique}: frame time against scene size ({rows[0][4]})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
