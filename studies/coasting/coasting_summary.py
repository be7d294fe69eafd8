#!/usr/bin/env python3
"""Summarises coasting_study.sh's flights: for each DIR:START:DURATION (DIR holds
clean/, texture/ and texture-held/, each with nadir_eval's series.csv and
metrics.json) one markdown row per run: final horizontal and vertical error, the
reported sigmas at the end, and over the outage (START to START + DURATION + 3 s)
the largest horizontal error, the largest change of the vertical error from just
before it, the largest change of the vertical error from one coasting pose to
the next (what a height loop flying on the pose would feel), the sigmas at its
end, and the final 3-D error over the clean flight's. texture/overlay.txt, when there, names the texture run's overlay."""
import csv
import json
import math
import os
import sys


def series(folder):
    with open(os.path.join(folder, "series.csv")) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def row(folder, start, length, clean_3d):
    s = series(folder)
    m = json.load(open(os.path.join(folder, "metrics.json")))
    end = start + length
    before = [r for r in s if r["t_s"] < start]
    inside = [r for r in s if start <= r["t_s"] <= end + 3.0]
    last_in = [r for r in s if r["t_s"] <= end][-1]
    v0 = before[-1]["error_v_m"] if before else 0.0
    coasting = [r["error_v_m"] for r in s if int(r["flags"]) & 16]  # pose_t::FLAG_COASTING
    jump = max((abs(b - a) for a, b in zip(coasting, coasting[1:])), default=0.0)
    f = s[-1]
    return (f"{m['final_error_h_m']:.2f} | {m['final_error_v_m']:+.2f} | {m['final_error_3d_m']:.2f} "
            f"({m['error_pct_3d']:.3f} %) | {f['sigma_h_m']:.2f} / {f['sigma_d_m']:.2f} | "
            f"{max(r['error_h_m'] for r in inside):.2f} | "
            f"{max(abs(r['error_v_m'] - v0) for r in inside):.2f} | {jump:.2f} | "
            f"{last_in['sigma_h_m']:.2f} / {last_in['sigma_d_m']:.2f} | "
            + (f"{m['final_error_3d_m'] / clean_3d:.2f}" if clean_3d else ""))


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) > 1 else 2
    print("| flight | run | final error h (m) | final v (m) | final 3-D (m, % of distance) | σh / σv at end (m) "
          "| max error h in outage (m) | max vertical excursion in outage (m) "
          "| largest pose-to-pose vertical jump (m) | σh / σv at outage end (m) | final 3-D / clean |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for arg in sys.argv[1:]:
        folder, start, length = arg.rsplit(":", 2)
        name = os.path.basename(folder)
        named = os.path.join(folder, "texture", "overlay.txt")
        overlay = open(named).read().strip() if os.path.exists(named) else "follow_altimeter"
        clean = os.path.join(folder, "clean", "metrics.json")
        clean_3d = json.load(open(clean))["final_error_3d_m"] if os.path.exists(clean) else None
        for run, label in (("clean", "no outage"), ("texture-held", "outage, climb held"),
                           ("texture", f"outage, {overlay}")):
            path = os.path.join(folder, run)
            if not os.path.exists(os.path.join(path, "series.csv")):
                continue
            print(f"| {name} | {label} | {row(path, float(start), float(length), clean_3d)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
