#!/usr/bin/python3
"""How far a coast's held track is off after D seconds, from every second of a
simulated flight (docs/research/2026-12-coasting.md, "The held track").

A coast holds the last velocity in the level vehicle frame and turns it with the
heading the INS keeps measuring. Which heading the velocity is put into that frame
with matters: the heading swings about the track (the simulator's seeded attitude
oscillations, a real aircraft's sideslip and yaw wander) and the track does not
follow the swing. For a coast starting at each second of the flight, the truth
positions stand in for the integrated ones and the simulated INS yaw for the fused
yaw, and the displacement D seconds on is predicted with:

  last frame      the last second's velocity in the frame of the last INS heading
                  (what yaw fusion did before)
  window mean     the displacement over the last W seconds in the frame of the mean
                  INS heading over the same seconds (held_level_velocity)
  track fixed     the window's track held in the world, no turn followed

and the window mean integrated in steps of one frame (14 Hz), 5 s (a photo
flight) and the whole coast, each step turned with the heading at its start
(yaw fusion before 2026-12-04) or its middle; and along the INS heading every
0.1 s whatever the step (yaw fusion since).

Usage: held_track.py SIM_LOG [SIM_LOG ...] [--coast-s 10] [--window-s 3]
Prints, per method, the rms, median, 90th percentile and largest error (metres)
of the predicted displacement over all start times and logs.
"""
import argparse
import csv
import io
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
NADIR_LOG = os.path.join(ROOT, "build", "bin", "nadir_log")


def dump(log, channel):
    out = subprocess.run([NADIR_LOG, "dump", log, channel], check=True, capture_output=True, text=True).stdout
    return list(csv.DictReader(io.StringIO(out)))


def predictions(log, coast_s, window_s, smooth_s=(), smooth_degrees=(1,), turn_deg=(), step_s=0.0714):
    truth = dump(log, "GROUND_TRUTH")
    ins = dump(log, "INS")
    tg = np.array([int(r["utime"]) for r in truth]) * 1e-6
    order = np.argsort(tg, kind="stable")
    tg = tg[order]
    pos = np.array([[float(truth[i]["north"]), float(truth[i]["east"])] for i in order])
    ti = np.array([int(r["utime"]) for r in ins]) * 1e-6
    yaw = np.unwrap(np.array([float(r["yaw"]) for r in ins]))

    def at(t):
        return np.array([np.interp(t, tg, pos[:, 0]), np.interp(t, tg, pos[:, 1])])

    def heading(t):
        return np.interp(t, ti, yaw)

    def mean_heading(t0, t1):
        m = (ti > t0) & (ti <= t1)
        return yaw[m].mean()

    errors = {"last frame": [], "window mean": [], "track fixed": []}
    for t0 in np.arange(tg[0] + window_s + 1.0, tg[-1] - coast_s, 1.0):
        truth_d = at(t0 + coast_s) - at(t0)
        v_last = at(t0) - at(t0 - 1.0)
        v_window = (at(t0) - at(t0 - window_s)) / window_s
        track_last = math.atan2(v_last[1], v_last[0])
        track_window = math.atan2(v_window[1], v_window[0])
        crab_last = track_last - heading(t0)
        crab_window = track_window - mean_heading(t0 - window_s, t0)
        speed = np.linalg.norm(v_window)
        times = np.arange(t0, t0 + coast_s, step_s)
        durations = np.diff(np.append(times, t0 + coast_s))

        def held(track_at):
            tracks = np.array([track_at(t) for t in times + durations])
            return speed * np.array([np.sum(durations * np.cos(tracks)), np.sum(durations * np.sin(tracks))])

        def held_at(point, step):
            """The window's velocity over steps of `step` s, each turned with the heading at
            its start (0), middle (0.5) or end (1)."""
            starts = np.arange(t0, t0 + coast_s, step)
            lengths = np.diff(np.append(starts, t0 + coast_s))
            tracks = crab_window + heading(starts + point * lengths)
            return speed * np.array([np.sum(lengths * np.cos(tracks)), np.sum(lengths * np.sin(tracks))])

        errors["last frame"].append(np.linalg.norm(held(lambda t: crab_last + heading(t)) - truth_d))
        errors["window mean"].append(np.linalg.norm(held(lambda t: crab_window + heading(t)) - truth_d))
        errors["track fixed"].append(np.linalg.norm(held(lambda t: track_window) - truth_d))
        for step in (step_s, 5.0, coast_s):
            for point, name in ((0.0, "its start"), (0.5, "its middle")):
                errors.setdefault(f"window mean, {step:g} s steps turned with the heading at {name}", []).append(
                    np.linalg.norm(held_at(point, step) - truth_d))
        errors.setdefault("window mean, one step along the INS heading every 0.1 s", []).append(
            np.linalg.norm(held_at(0.5, 0.1) - truth_d))
        # The heading smoothed before it turns the velocity: at each time, a
        # straight line fitted to the INS headings within +-h s of it (only those
        # from the window's start to the coast's end: all are known when VO
        # returns), so a steady turn is followed without lag and a swing shorter
        # than the fit is not. The window's crab taken against the same heading.
        lo, hi = t0 - window_s, t0 + coast_s
        span = (ti >= lo) & (ti <= hi)
        ts_, ys_ = ti[span], yaw[span]

        def smooth(t, h, degree):
            m = np.abs(ts_ - t) <= h
            if m.sum() < degree + 2:
                return heading(t)
            return np.polyfit(ts_[m] - t, ys_[m], degree)[-1]

        # A turn or not: the straight line through all the INS headings from the
        # window's start to the coast's end; where it turns by less than
        # `threshold` degrees over that span, the window's track is held fixed
        # (the heading's swing is not followed), else the heading as above.
        slope = np.polyfit(ts_ - t0, ys_, 1)[0] if len(ts_) > 2 else 0.0
        for threshold in turn_deg:
            straight = abs(math.degrees(slope) * (coast_s + window_s)) < threshold
            pred = held(lambda t: track_window) if straight else held_at(0.5, 0.1)
            errors.setdefault(f"track fixed unless the heading turns by {threshold:g} deg", []).append(
                np.linalg.norm(pred - truth_d))
        for h, degree in ((h, d) for h in smooth_s for d in smooth_degrees):
            grid = np.arange(t0 - window_s, t0 + coast_s + 1e-9, 0.1)
            sm = np.array([smooth(t, h, degree) for t in grid])
            crab_s = track_window - sm[grid <= t0 + 1e-9].mean()
            mids = np.arange(t0, t0 + coast_s, 0.1) + 0.05
            tracks = crab_s + np.interp(mids, grid, sm)
            pred = speed * 0.1 * np.array([np.sum(np.cos(tracks)), np.sum(np.sin(tracks))])
            errors.setdefault(f"along the INS heading smoothed +-{h:g} s, degree {degree}", []).append(np.linalg.norm(pred - truth_d))
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("logs", nargs="+", help="simulator logs (nadir_sim --out)")
    parser.add_argument("--coast-s", type=float, default=10.0)
    parser.add_argument("--window-s", type=float, default=3.0, help="yaw_fusion.coast.speed_window_s")
    parser.add_argument("--smooth-s", type=float, nargs="*", default=[],
                        help="half-widths (s) of the line fitted to the INS heading, one method each")
    parser.add_argument("--turn-deg", type=float, nargs="*", default=[],
                        help="thresholds (deg over the window and the coast) below which the track is held fixed")
    parser.add_argument("--smooth-degrees", type=int, nargs="*", default=[1],
                        help="degrees of the polynomial fitted over each half-width")
    args = parser.parse_args()
    if not os.access(NADIR_LOG, os.X_OK):
        sys.exit(f"held_track: error: {NADIR_LOG} not built (launch_scripts/setup.sh)")
    total = {}
    for log in args.logs:
        if not os.path.isfile(log):
            sys.exit(f"held_track: error: {log}: no such file")
        for method, e in predictions(log, args.coast_s, args.window_s, args.smooth_s, args.smooth_degrees, args.turn_deg).items():
            total.setdefault(method, []).extend(e)
    n = len(next(iter(total.values())))
    print(f"{n} coasts of {args.coast_s:g} s from {len(args.logs)} flight(s), window {args.window_s:g} s")
    print("| held track | rms (m) | median (m) | 90 % (m) | max (m) |")
    print("|---|---|---|---|---|")
    for method, e in total.items():
        e = np.array(e)
        print(f"| {method} | {math.sqrt(np.mean(e ** 2)):.2f} | {np.median(e):.2f} | "
              f"{np.percentile(e, 90):.2f} | {e.max():.2f} |")


if __name__ == "__main__":
    main()
