#!/usr/bin/python3
"""The featureless crossing with and without map fixes: horizontal error and
reported sigma against time, the fixes applied marked, the time over the
featureless box shaded.

Usage: plot_crossing.py WITH_MAP_REPORT NO_MAP_REPORT NORTH_MIN NORTH_MAX EAST_MIN EAST_MAX OUT.png
(reports: nadir_eval --out folders, as studies/map_fixes/long_flights.sh writes them)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLAG_MAP_FIX_APPLIED = 32


def series(report):
    with open(f"{report}/series.csv") as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def main(argv):
    if len(argv) != 8:
        sys.exit(__doc__)
    with_map, no_map = series(argv[1]), series(argv[2])
    box = [float(v) for v in argv[3:7]]
    inside = [r["t_s"] for r in with_map
              if box[0] <= r["true_n"] <= box[1] and box[2] <= r["true_e"] <= box[3]]
    fig, ax = plt.subplots(figsize=(10, 4.5))
    if inside:
        ax.axvspan(min(inside), max(inside), color="0.9", label="over the featureless area")
    t = [r["t_s"] for r in no_map]
    ax.plot(t, [r["error_h_m"] for r in no_map], color="tab:red", lw=1.2, label="error, no map")
    ax.plot(t, [r["sigma_h_m"] for r in no_map], color="tab:red", lw=0.8, ls="--", label="σ, no map")
    t = [r["t_s"] for r in with_map]
    ax.plot(t, [r["error_h_m"] for r in with_map], color="tab:blue", lw=1.2, label="error, with map fixes")
    ax.plot(t, [r["sigma_h_m"] for r in with_map], color="tab:blue", lw=0.8, ls="--", label="σ, with map fixes")
    fixes = [r["t_s"] for r in with_map if int(r["flags"]) & FLAG_MAP_FIX_APPLIED]
    ax.plot(fixes, [-1.0] * len(fixes), "|", color="tab:green", ms=8, label="fix applied")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("horizontal (m)")
    ax.set_ylim(bottom=-2.5)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title("featureless_crossing seed 1: 40 km at 300 m, the middle 20 km over contrast 0.08")
    fig.tight_layout()
    fig.savefig(argv[7], dpi=110)


if __name__ == "__main__":
    main(sys.argv)
