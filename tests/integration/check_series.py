#!/usr/bin/env python3
"""Checks a nadir_eval series.csv for reliability tests.

  check_series.py SERIES.csv --max-velocity-error 5
      every pose's velocity error is within +-5 m/s of the truth (per axis) after
      the first second: the first pose has no motion yet (its velocity is zero), and
      the first second's steps are solved with the INS attitude alone, each frame's
      attitude noise on the ground (~0.25 m at 200 m, standard sensors) over 0.07 s,
      until the tracked features have depths of their own
  check_series.py SERIES.csv --restart-after T
      after time T (s) no pose restarts at the origin (FLAG_INITIALIZING) and
      every pose's horizontal error is within 3 sigma of what it reports
      (+1 m for the simulated flight's own error); prints the largest ratio
"""
import argparse
import csv
import sys

FLAG_VO_GAP, FLAG_INITIALIZING = 1, 8


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("series")
    ap.add_argument("--max-velocity-error", type=float)
    ap.add_argument("--restart-after", type=float)
    a = ap.parse_args()
    with open(a.series) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    if not rows:
        sys.exit(f"check_series: {a.series} has no poses")
    bad = []
    if a.max_velocity_error is not None:
        settled = [r for r in rows if r["t_s"] >= 1.0]
        worst = max(max(abs(r[k]) for k in ("vel_err_n", "vel_err_e", "vel_err_d")) for r in settled)
        print(f"check_series: largest velocity error {worst:.2f} m/s over {len(settled)} poses after the first second")
        if worst > a.max_velocity_error:
            bad.append(f"velocity error {worst:.2f} m/s > {a.max_velocity_error}")
    if a.restart_after is not None:
        after = [r for r in rows if r["t_s"] > a.restart_after]
        gaps = [r for r in after if int(r["flags"]) & FLAG_VO_GAP]
        if any(int(r["flags"]) & FLAG_INITIALIZING for r in after):
            bad.append("a pose after the restart is INITIALIZING (position restarted)")
        if not gaps:
            bad.append("no pose after the restart is flagged VO_GAP")
        worst = max(r["error_h_m"] / (3.0 * r["sigma_h_m"] + 1.0) for r in after)
        print(f"check_series: {len(after)} poses after {a.restart_after} s, {len(gaps)} flagged VO_GAP; "
              f"largest error / (3 sigma + 1 m) = {worst:.2f}")
        if worst > 1.0:
            bad.append(f"horizontal error beyond 3 sigma + 1 m (ratio {worst:.2f})")
    for b in bad:
        print("check_series: FAIL: " + b)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
