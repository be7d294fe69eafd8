#!/usr/bin/python3
"""Markdown tables comparing solver variants over several flights and seeds.

Reads ROOT/<profile>-<seed>-<variant>/metrics.json (nadir_eval output) and
prints, per profile, the final 3-D error and the RMS 3-D error over the whole
flight as % of distance flown, each the mean over the profile's seeds; then
the margin of the first variant over the best of the others (positive: the
first variant is more accurate), and the same figures per seed.

Usage: variant_table.py --root DIR --variants paper,homography,... PROFILE=SEED[,SEED...] ..."""
import argparse
import json
import sys

METRICS = (("final", "error_pct_3d"), ("RMS", "rms_error_pct_3d"))


def load(root, profile, seed, variant):
    path = f"{root}/{profile}-{seed}-{variant}/metrics.json"
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise SystemExit(f"variant_table: error: {path}: {e}")


def table(title, columns, variants, value):
    """One markdown table: a row per variant, the best value per column in bold."""
    print(f"| {title} | " + " | ".join(name for name, _ in columns) + " |")
    print("|---" * (1 + len(columns)) + "|")
    for v in variants:
        cells = []
        for _, column in columns:
            x, best = value(v, column), min(value(w, column) for w in variants)
            cells.append(f"**{x:.3f}**" if x == best else f"{x:.3f}")
        print(f"| `{v}` | " + " | ".join(cells) + " |")
    print()


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--root", required=True)
    p.add_argument("--variants", required=True, help="comma-separated; the first is compared with the others")
    p.add_argument("runs", nargs="+", help="PROFILE=SEED[,SEED...]")
    a = p.parse_args()
    variants = a.variants.split(",")
    if len(variants) < 2:
        print("variant_table: error: --variants needs at least two", file=sys.stderr)
        return 2
    runs = []
    for run in a.runs:
        if "=" not in run:
            print(f"variant_table: error: '{run}' is not PROFILE=SEED[,SEED...]", file=sys.stderr)
            return 2
        profile, seeds = run.split("=", 1)
        runs.append((profile, seeds.split(",")))
    m = {(t, s, v): load(a.root, t, s, v) for t, seeds in runs for s in seeds for v in variants}

    def mean(v, column):
        (t, seeds), key = column
        return sum(m[(t, s, v)][key] for s in seeds) / len(seeds)

    columns = [(f"{t} {name} % (mean of {len(seeds)})", ((t, seeds), key)) for t, seeds in runs for name, key in METRICS]
    table("variant", columns, variants, mean)

    first, others = variants[0], variants[1:]
    cells = []
    for name, column in columns:
        best = min(others, key=lambda w: mean(w, column))
        cells.append(f"{mean(best, column) - mean(first, column):+.3f} pp vs `{best}`")
    print(f"| margin of `{first}` over the best other variant (positive: more accurate) | " +
          " | ".join(name for name, _ in columns) + " |")
    print("|---" * (1 + len(columns)) + "|")
    print("| | " + " | ".join(cells) + " |")
    print()

    print("| flight | " + " | ".join(f"`{v}` {name} %" for v in variants for name, _ in METRICS) + " |")
    print("|---" * (1 + len(variants) * len(METRICS)) + "|")
    for t, seeds in runs:
        for s in seeds:
            cells = []
            for v in variants:
                for _, key in METRICS:
                    x, best = m[(t, s, v)][key], min(m[(t, s, w)][key] for w in variants)
                    cells.append(f"**{x:.3f}**" if x == best else f"{x:.3f}")
            print(f"| {t} seed {s} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
