#!/usr/bin/python3
"""Each pair's step error along and across its true step, in time bins, for one or more replays of a flight.

Usage: pair_errors.py [--from S] [--to S] [--bin S] DIR [DIR ...]

DIR: a nadir_eval folder (its pairs.csv). Per bin of --bin seconds (default 1)
between --from and --to (seconds after the first frame): the mean along-step and
across-step error of the pairs ending in it, in % of the true step, and the true
heading rate (deg/s) from the first DIR. The DIRs are replays of the same
flight (e.g. relief_sigma.sh's default/ and a replay with other options), one
column pair each, so a bias that follows the manoeuvre shows side by side
(docs/research/2026-12-relief-sigma.md, "Turns over relief")."""
import argparse
import csv
import math
import os
import sys


def binned(path, start_s, end_s, bin_s):
    """{bin: (mean along %, mean across %, mean true heading rate deg/s)} of pairs.csv."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no pairs")
    t0 = int(rows[0]["prev_utime"])
    bins = {}
    for r in rows:
        tx, ty = float(r["true_x"]), float(r["true_y"])
        step = math.hypot(tx, ty)
        if step < 1e-3:
            continue
        ex, ey = float(r["dx"]) - tx, float(r["dy"]) - ty
        t = (int(r["utime"]) - t0) * 1e-6
        if not start_s <= t < end_s:
            continue
        dt = (int(r["utime"]) - int(r["prev_utime"])) * 1e-6
        along = (ex * tx + ey * ty) / step / step * 100.0
        across = (-ex * ty + ey * tx) / step / step * 100.0
        rate = float(r["true_dyaw_deg"]) / dt if dt > 0 else 0.0
        bins.setdefault(int((t - start_s) // bin_s), []).append((along, across, rate))
    return {k: tuple(sum(v[i] for v in vs) / len(vs) for i in range(3)) for k, vs in bins.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--from", dest="start", type=float, default=0.0, metavar="S")
    parser.add_argument("--to", dest="end", type=float, default=float("inf"), metavar="S")
    parser.add_argument("--bin", type=float, default=1.0, metavar="S")
    parser.add_argument("dirs", nargs="+", metavar="DIR")
    args = parser.parse_args()
    if args.bin <= 0:
        parser.error("--bin must be > 0")
    tables = []
    for d in args.dirs:
        path = os.path.join(d, "pairs.csv")
        try:
            tables.append(binned(path, args.start, args.end, args.bin))
        except (OSError, ValueError, KeyError) as e:
            sys.exit(f"pair_errors: {path}: {e}")
    labels = [os.path.join(*os.path.normpath(d).split(os.sep)[-2:])[-20:] for d in args.dirs]
    print("t_s    rate_dps " + " ".join(f"{label:>20}" for label in labels))
    print("                " + " ".join(f"{'along %':>10}{'across %':>10}" for _ in args.dirs))
    for k in sorted(tables[0]):
        t = args.start + k * args.bin
        cells = " ".join(f"{tb[k][0]:+10.2f}{tb[k][1]:+10.2f}" if k in tb else f"{'':>20}" for tb in tables)
        print(f"{t:6.1f} {tables[0][k][2]:+8.1f} {cells}")


if __name__ == "__main__":
    main()
