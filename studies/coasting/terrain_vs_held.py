#!/usr/bin/env python3
"""How well each vertical model would have predicted the height 10 s ahead, for a
coast starting at every second of a clean flight (truth from GROUND_TRUTH):
  plane  the ground below the coast's end from the last 1 s of VO ground-patch
         slopes (yaw_fusion.coast.follow_altimeter; the range itself taken as exact)
  flat   the ground held level
  half   half the plane's slope
  held   the true climb rate of the last 3 s held (the old coast, without its VO noise)
  mix    the mean of plane and held
Usage: terrain_vs_held.py VO_DELTA.csv GROUND_TRUTH.csv POSE.csv [COAST_S]
(CSV files from `nadir_log dump REPLAY.lcmlog CHANNEL -o FILE` of a clean replay)."""
import bisect
import csv
import math
import statistics as st
import sys


def main():
    if len(sys.argv) < 4:
        print(__doc__)
        return 2
    coast_us = int(float(sys.argv[4]) * 1e6) if len(sys.argv) > 4 else 10_000_000
    vo = list(csv.DictReader(open(sys.argv[1])))
    gt = [r for r in csv.DictReader(open(sys.argv[2])) if r["kind"] == "1"]  # KIND_FRAME
    pose = {r["utime"]: r for r in csv.DictReader(open(sys.argv[3]))}
    times = [int(r["utime"]) for r in gt]

    def truth(u):
        i = min(max(bisect.bisect_left(times, u), 0), len(gt) - 1)
        return gt[i]

    slopes = []  # (utime, d down / d north, d down / d east), as coast_terrain.cc
    for d in vo:
        if d["utime"] not in pose or int(d["quality"]) & 1:
            continue
        r, p, y = float(d["ground_roll"]), float(d["ground_pitch"]), float(pose[d["utime"]]["yaw"])
        fwd, right = -math.tan(p), math.tan(r) / math.cos(p)
        slopes.append((int(d["utime"]), math.cos(y) * fwd - math.sin(y) * right, math.sin(y) * fwd + math.cos(y) * right))
    slope_times = [s[0] for s in slopes]

    def slope(u):
        window = slopes[bisect.bisect_left(slope_times, u - 1_000_000):bisect.bisect_right(slope_times, u)]
        return st.mean(s[1] for s in window), st.mean(s[2] for s in window)

    err = {"plane": [], "flat": [], "half": [], "held": [], "mix": []}
    for u in range(times[0] + 5_000_000, times[-1] - coast_us - 1_000_000, 1_000_000):
        a, b, c = truth(u), truth(u + coast_us), truth(u - 3_000_000)
        g0, g1 = -float(a["terrain_height_m"]), -float(b["terrain_height_m"])
        dn, de = float(b["north"]) - float(a["north"]), float(b["east"]) - float(a["east"])
        gn, ge = slope(u)
        err["plane"].append(g0 + gn * dn + ge * de - g1)
        err["flat"].append(g0 - g1)
        err["half"].append(g0 + 0.5 * (gn * dn + ge * de) - g1)
        climb = (float(a["down"]) - float(c["down"])) / 3.0
        err["held"].append(float(a["down"]) + climb * coast_us * 1e-6 - float(b["down"]))
        err["mix"].append(0.5 * (err["plane"][-1] + err["held"][-1]))
    print("| model | coasts | rms (m) | median abs (m) | 90 % (m) | max (m) |")
    print("|---|---|---|---|---|---|")
    for name, e in err.items():
        a = sorted(abs(x) for x in e)
        print(f"| {name} | {len(e)} | {math.sqrt(st.mean(x * x for x in e)):.2f} | {st.median(a):.2f} | "
              f"{a[int(0.9 * len(a))]:.2f} | {a[-1]:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
