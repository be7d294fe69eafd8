#!/usr/bin/env python3
"""Summarises coasting_study.sh's flights: for each DIR:START:DURATION (DIR holds
clean/, texture/ and texture-held/, each with nadir_eval's series.csv and
metrics.json) one markdown row per run: final horizontal and vertical error, the
reported sigmas at the end, and over the outage (START to START + DURATION + 3 s)
the largest horizontal error, the largest change of the vertical error from just
before it, and the sigmas at its end."""
import csv
import json
import math
import os
import sys


def series(folder):
    with open(os.path.join(folder, "series.csv")) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def row(folder, start, length):
    s = series(folder)
    m = json.load(open(os.path.join(folder, "metrics.json")))
    end = start + length
    before = [r for r in s if r["t_s"] < start]
    inside = [r for r in s if start <= r["t_s"] <= end + 3.0]
    last_in = [r for r in s if r["t_s"] <= end][-1]
    v0 = before[-1]["error_v_m"] if before else 0.0
    f = s[-1]
    return (f"{m['final_error_h_m']:.2f} | {m['final_error_v_m']:+.2f} | {m['final_error_3d_m']:.2f} "
            f"({m['error_pct_3d']:.3f} %) | {f['sigma_h_m']:.2f} / {f['sigma_d_m']:.2f} | "
            f"{max(r['error_h_m'] for r in inside):.2f} | "
            f"{max(abs(r['error_v_m'] - v0) for r in inside):.2f} | "
            f"{last_in['sigma_h_m']:.2f} / {last_in['sigma_d_m']:.2f}")


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) > 1 else 2
    print("| flight | run | final error h (m) | final v (m) | final 3-D (m, % of distance) | σh / σv at end (m) "
          "| max error h in outage (m) | max vertical excursion in outage (m) | σh / σv at outage end (m) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for arg in sys.argv[1:]:
        folder, start, length = arg.rsplit(":", 2)
        name = os.path.basename(folder)
        for run, label in (("clean", "no outage"), ("texture-held", "outage, climb held (before)"),
                           ("texture", "outage, altimeter followed")):
            path = os.path.join(folder, run)
            if not os.path.exists(os.path.join(path, "series.csv")):
                continue
            # The clean flight over the same window: what the outage adds.
            print(f"| {name} | {label} | {row(path, float(start), float(length))} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
