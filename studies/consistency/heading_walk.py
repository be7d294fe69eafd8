#!/usr/bin/python3
"""How the VO's chained heading error grows with the number of pairs.

Usage: heading_walk.py [--json] DIR [DIR ...]

Each DIR holds one folder per flight with nadir_eval's pairs.csv (a
campaign's cells, or eval folders). Each solved pair's heading change error
(dyaw_deg - true_dyaw_deg) is summed over every window of N consecutive
solved pairs, N = 50 to 1,200. The levelling part of each pair's error
telescopes (a window keeps only its two end frames'), so the mean square of
the sums is a constant plus N times the per-pair variance of what does not
telescope: fitted here by least squares, per flight and pooled. The VO
solver's model of that part is vo_solver.uncertainty.dyaw_model_stddev_deg
(0.005 deg per pair) plus the image noise."""
import csv
import json
import sys

import numpy as np

from flight_files import flight_files

WINDOWS = (50, 100, 200, 400, 800, 1200)


def heading_errors(path):
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["solved"] == "1"]
    e = np.array([float(r["dyaw_deg"]) - float(r["true_dyaw_deg"]) for r in rows])
    return (e + 180.0) % 360.0 - 180.0


def fit(errors):
    """(walk deg per pair, constant deg, {N: rms deg}) of the summed errors."""
    c = np.concatenate([[0.0], np.cumsum(errors)])
    ns = [n for n in WINDOWS if 2 * n < len(c)]
    if len(ns) < 2:
        return None
    ms = np.array([np.mean((c[n:] - c[:-n]) ** 2) for n in ns])
    slope, constant = np.polyfit(np.array(ns, dtype=float), ms, 1)
    return slope, constant, {n: float(np.sqrt(m)) for n, m in zip(ns, ms)}


def main(argv):
    as_json = "--json" in argv
    dirs = [a for a in argv if a != "--json"]
    if not dirs or "--help" in argv or "-h" in argv:
        print(__doc__)
        return 0 if dirs or "--help" in argv or "-h" in argv else 2
    flights, slopes = [], []
    for name, path in flight_files(dirs, "pairs.csv", "heading_walk"):
        result = fit(heading_errors(path))
        if result is None:
            continue
        slope, constant, rms = result
        slopes.append(slope)
        flights.append({"flight": name, "walk_deg_per_pair": float(np.sqrt(max(slope, 0.0))),
                        "constant_deg": float(np.sqrt(max(constant, 0.0))), "rms_deg": rms})
    if not flights:
        raise SystemExit("heading_walk: error: no flight with enough solved pairs in " + " ".join(dirs))
    pooled = float(np.sqrt(max(np.mean(slopes), 0.0)))
    if as_json:
        print(json.dumps({"flights": flights, "pooled_walk_deg_per_pair": pooled}, indent=1))
        return 0
    for f in flights:
        sums = " ".join(f"{n}:{v:.4f}" for n, v in f["rms_deg"].items())
        print(f"{f['flight']:36s} walk {f['walk_deg_per_pair']:.5f} deg/pair, ends {f['constant_deg']:.4f} deg; "
              f"rms of sums (pairs:deg) {sums}")
    print(f"{len(flights)} flights, pooled walk {pooled:.5f} deg per pair")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
