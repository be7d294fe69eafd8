#!/usr/bin/env python3
"""The table of launch_scripts/reliability.sh: one row per fault case.

Usage: reliability_table.py OUT_DIR CASE...   (reads OUT_DIR/CASE/metrics.json and OUT_DIR/CASE.txt)
"""
import json
import os
import sys


def load(out, case):
    path = os.path.join(out, case, "metrics.json")
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def main():
    out, cases = sys.argv[1], sys.argv[2:]
    clean = load(out, "clean")
    print("| case | final error % | vs clean | rms velocity error m/s | poses (flagged) | dropped by processes "
          "| malformed | process deaths | capture holes (longest s) | missing from capture | kernel drops (datagrams) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case in cases:
        m = load(out, case)
        log = os.path.join(out, case + ".txt")
        deaths = 0
        if os.path.exists(log):
            with open(log, errors="replace") as f:
                deaths = sum(1 for line in f if "] " in line and " died (exit" in line)
        if m is None:
            print(f"| {case} | no result (see {log}) | | | | | | {deaths} | | | |")
            continue
        procs = m.get("processes", {})
        dropped = sum(p["dropped"] for p in procs.values())
        malformed = sum(p["malformed"] for p in procs.values())
        ratio = f"{m['error_pct_3d'] / clean['error_pct_3d']:.2f}x" if clean else "-"
        kernel = ", ".join(f"{name} {p['udp_rx_drops']}" for name, p in sorted(procs.items())
                           if p.get("udp_rx_drops", 0) > 0) or "0"
        print(f"| {case} | {m['error_pct_3d']:.3f} | {ratio} | {m['rms_velocity_error_h']:.2f} | "
              f"{m['poses']} ({m['poses_flagged']}) | {dropped} | {malformed} | {deaths} | "
              f"{m['capture_holes']} ({m['capture_longest_hole_s']:.2f}) | {m.get('capture_missing', 0)} | {kernel} |")


if __name__ == "__main__":
    main()
