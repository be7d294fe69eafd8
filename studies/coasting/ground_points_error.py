#!/usr/bin/env python3
"""How far the VO_GROUND points lie from the simulated ground, placed with the
true pose (docs/research/2026-12-coasting.md, "A height filter over the seen
ground"): each point of each frame is put in the world with the vehicle's true
position and heading at the frame, and compared with the terrain where the
vehicle later flew over it (points within 2 m of the flown path; the truth
only knows the terrain below the vehicle). Printed: the error by distance
ahead of the vehicle and by reported relative depth sigma, and the per-frame
offset and slope of the errors (what one frame's cloud shares).
Usage: ground_points_error.py GROUND.csv GROUND_TRUTH.csv
  GROUND.csv:       nadir_log dump REPLAY.lcmlog VO_GROUND -o GROUND.csv
  GROUND_TRUTH.csv: nadir_log dump SIM.lcmlog GROUND_TRUTH -o GROUND_TRUTH.csv"""
import sys
from collections import defaultdict

import numpy as np
from scipy.spatial import cKDTree


def main():
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help") else 2
    g = np.genfromtxt(sys.argv[1], delimiter=",", names=True)
    t = np.genfromtxt(sys.argv[2], delimiter=",", names=True)
    t = t[t["kind"] == 2]  # KIND_INS: 100 Hz, interpolated to each frame's time
    tu, gu = t["utime"].astype(float), g["utime"].astype(float)
    yaw = np.interp(gu, tu, np.unwrap(t["yaw"]))
    north = np.interp(gu, tu, t["north"]) + np.cos(yaw) * g["x_m"] - np.sin(yaw) * g["y_m"]
    east = np.interp(gu, tu, t["east"]) + np.sin(yaw) * g["x_m"] + np.cos(yaw) * g["y_m"]
    down = np.interp(gu, tu, t["down"]) + g["z_m"]
    distance, nearest = cKDTree(np.c_[t["north"], t["east"]]).query(np.c_[north, east])
    near = distance < 2.0
    error = down + t["terrain_height_m"][nearest]  # the ground's down is -terrain height
    relative_sigma = g["depth_sigma_m"] / g["z_m"]
    ahead = g["x_m"]
    print(f"points {len(g)}, within 2 m of the path {near.sum()}")
    print("| ahead of the vehicle (m) | points | mean error (m) | sd (m) | reported sigma, median (m) |")
    print("|---|---|---|---|---|")
    for lo, hi in [(-120, -60), (-60, -20), (-20, 20), (20, 50), (50, 80), (80, 120)]:
        m = near & (ahead >= lo) & (ahead < hi)
        if m.sum() >= 10:
            print(f"| {lo} to {hi} | {m.sum()} | {error[m].mean():+.3f} | {error[m].std():.3f} | "
                  f"{np.median(g['depth_sigma_m'][m]):.3f} |")
    print()
    print("| depth sigma / depth | points | mean error (m) | sd (m) | rms of error / sigma |")
    print("|---|---|---|---|---|")
    for lo, hi in [(0, 0.005), (0.005, 0.01), (0.01, 0.02), (0.02, 0.03)]:
        m = near & (relative_sigma >= lo) & (relative_sigma < hi)
        if m.sum() >= 10:
            z = error[m] / g["depth_sigma_m"][m]
            print(f"| {lo:.3f} to {hi:.3f} | {m.sum()} | {error[m].mean():+.3f} | {error[m].std():.3f} | "
                  f"{np.sqrt((z * z).mean()):.2f} |")
    frames = defaultdict(list)
    for u, e, x, n in zip(g["utime"], error, ahead, near):
        if n:
            frames[u].append((x, e))
    offsets, slopes = [], []
    for pts in frames.values():
        pts = np.array(pts)
        if len(pts) >= 6 and np.ptp(pts[:, 0]) >= 60:
            slope, offset = np.polyfit(pts[:, 0], pts[:, 1], 1)
            offsets.append(offset)
            slopes.append(slope)
    if offsets:
        print(f"\nper frame ({len(offsets)} frames with points spanning 60 m of the path): offset "
              f"{np.mean(offsets):+.3f} +- {np.std(offsets):.3f} m, slope {np.mean(slopes):+.5f} +- "
              f"{np.std(slopes):.5f} (x 80 m: {80 * np.std(slopes):.2f} m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
