#!/usr/bin/env python3
"""The bound on a coast over ground already seen (docs/research/2026-12-coasting.md,
"The ground already seen"): for a 10 s coast starting at every second of a flight
(truth from GROUND_TRUTH), the height error 10 s on when the ground is known
for the first KNOWN metres ahead of the last frame (the range then gives the
height exactly) and the climb rate of the last second over it is held for the
rest, against the true climb of the last 3 s held for the whole coast.
Usage: seen_ahead.py GROUND_TRUTH.csv [KNOWN_M ...]   (default 115 90 60)
(a CSV from `nadir_log dump SIM.lcmlog GROUND_TRUTH -o FILE`)."""
import bisect
import csv
import math
import statistics as st
import sys


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) > 1 else 2
    gt = [r for r in csv.DictReader(open(sys.argv[1])) if r["kind"] == "1"]  # KIND_FRAME
    known_m = [float(k) for k in sys.argv[2:]] or [115.0, 90.0, 60.0]
    times = [int(r["utime"]) for r in gt]

    def at(u):
        return gt[min(max(bisect.bisect_left(times, u), 0), len(gt) - 1)]

    def down(r):
        return float(r["down"])

    def stats(errors):
        a = sorted(abs(e) for e in errors)
        return (f"rms {math.sqrt(st.mean(e * e for e in errors)):.2f} m, median {st.median(a):.2f}, "
                f"90 % {a[int(0.9 * len(a))]:.2f}, max {a[-1]:.2f}")

    starts = range(times[0] + 5_000_000, times[-1] - 11_000_000, 1_000_000)
    held = []
    for u in starts:
        a, before, end = at(u), at(u - 3_000_000), at(u + 10_000_000)
        held.append(down(a) + (down(a) - down(before)) / 3.0 * 10.0 - down(end))
    print(f"{len(held)} coasts of 10 s; climb of the last 3 s held: {stats(held)}")
    for known in known_m:
        errors = []
        for u in starts:
            a, end = at(u), at(u + 10_000_000)
            forward = (math.cos(float(a["yaw"])), math.sin(float(a["yaw"])))
            last_known = u
            for k in range(1, 101):  # 0.1 s steps: the last time the vehicle is over the known ground
                r = at(u + k * 100_000)
                along = ((float(r["north"]) - float(a["north"])) * forward[0] +
                         (float(r["east"]) - float(a["east"])) * forward[1])
                if along > known:
                    break
                last_known = u + k * 100_000
            r, r_before = at(last_known), at(last_known - 1_000_000)
            left_s = (u + 10_000_000 - last_known) * 1e-6
            errors.append(down(r) + (down(r) - down(r_before)) * left_s - down(end))
        print(f"ground known {known:.0f} m ahead, then its last climb held: {stats(errors)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
