#!/usr/bin/python3
"""What each texture outage of a flight adds to the horizontal error
(docs/research/2026-12-coasting.md, "The held track").

A flight simulated with several outages (nadir_sim --outage texture:START:LEN ...,
far enough apart that the coast has a clean speed window before each) and evaluated
(nadir_eval's series.csv) gives one coast per outage. For each, the horizontal
error vector (estimate - truth, north/east) at the last pose before the outage is
subtracted from the one at the outage's end and 3 s after it (the resume included):
what the coast added, whatever error the flight carried in.

Usage: outage_growth.py --length 10 --starts 20,45,70 RUN=EVAL_DIR [RUN=EVAL_DIR ...]
  RUN names a column (e.g. before=.../before after=.../after); runs of the same
  flight with different code line up outage by outage. Prints one row per outage
  and the rms, median and largest over them.
"""
import argparse
import math
import os
import statistics
import sys

from coasting_summary import series


def error_at(rows, t, before=False):
    """(north, east) error of the last pose before t, or of the first at or after t."""
    pick = [r for r in rows if r["t_s"] < t][-1] if before else next(r for r in rows if r["t_s"] >= t)
    return pick["est_n"] - pick["true_n"], pick["est_e"] - pick["true_e"]


def added(rows, start, end):
    e0 = error_at(rows, start, before=True)
    e1 = error_at(rows, end)
    return math.hypot(e1[0] - e0[0], e1[1] - e0[1])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--length", type=float, required=True, help="outage length (s)")
    parser.add_argument("--starts", required=True, help="outage start times (s), comma-separated")
    parser.add_argument("runs", nargs="+", help="NAME=EVAL_DIR")
    args = parser.parse_args()
    starts = [float(s) for s in args.starts.split(",")]
    runs = []
    for arg in args.runs:
        name, sep, folder = arg.partition("=")
        if not sep or not os.path.isfile(os.path.join(folder, "series.csv")):
            sys.exit(f"outage_growth: error: '{arg}' is not NAME=DIR with DIR/series.csv")
        runs.append((name, series(folder)))
    header = " | ".join(f"{n}: end / +3 s (m)" for n, _ in runs)
    print(f"| outage start (s) | {header} |")
    print("|---|" + "---|" * len(runs))
    table = {n: ([], []) for n, _ in runs}
    for start in starts:
        end = start + args.length
        cells = []
        for name, rows in runs:
            a, b = added(rows, start, end), added(rows, start, end + 3.0)
            table[name][0].append(a)
            table[name][1].append(b)
            cells.append(f"{a:.2f} / {b:.2f}")
        print(f"| {start:g} | " + " | ".join(cells) + " |")
    for label, f in (("rms", lambda v: math.sqrt(sum(x * x for x in v) / len(v))),
                     ("median", statistics.median), ("max", max)):
        print(f"| {label} | " + " | ".join(f"{f(table[n][0]):.2f} / {f(table[n][1]):.2f}" for n, _ in runs) + " |")


if __name__ == "__main__":
    main()
