#!/usr/bin/env python3
"""Frame-pair figures of a calibrated replay on the pairs a calibration did not
see: the pairs after --split-s seconds (from the first pair), before and after
the calibration (two pairs.csv files written by nadir_eval)."""
import argparse
import csv
import statistics
import sys


def held_out(path, split_s):
    try:
        rows = list(csv.DictReader(open(path)))
    except OSError as e:
        sys.exit(f"held_out_pairs: error: {e}")
    if not rows:
        sys.exit(f"held_out_pairs: error: {path}: no frame pairs")
    t0 = min(int(r["prev_utime"]) for r in rows)
    after = [r for r in rows if (int(r["prev_utime"]) - t0) * 1e-6 >= split_s]
    solved = [r for r in after if r["solved"] == "1"]
    errors = [float(r["error_pct"]) for r in solved if float(r["step_m"]) >= 0.5]
    median = statistics.median(errors) if errors else float("nan")
    return len(after), len(solved), median


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--split-s", type=float, required=True, help="pairs starting this long after the first are held out")
    parser.add_argument("--before", required=True, help="pairs.csv without the calibration")
    parser.add_argument("--after", required=True, help="pairs.csv with it")
    args = parser.parse_args()
    n0, solved0, median0 = held_out(args.before, args.split_s)
    n1, solved1, median1 = held_out(args.after, args.split_s)
    print(f"held-out pairs (after {args.split_s:g} s): {n1}; solved {solved0} -> {solved1}; "
          f"horizontal error per pair {median0:.1f} % -> {median1:.1f} % of the step (median)")


if __name__ == "__main__":
    main()
