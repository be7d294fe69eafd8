#!/usr/bin/python3
"""The tables of docs/research/2026-12-realistic-gap.md from realistic_gap.sh's output.

Usage: realistic_gap_summary.py [DIR]   (default: logs/realistic_gap under the checkout)

DIR holds one folder per evaluated run, PROFILE-SEED-RUN, RUN being `standard`,
`realistic-INSTALLATION` or `exact_heading-INSTALLATION`, each with nadir_eval's
metrics.json. Prints, for every run kind, the final 3-D error (% of distance) and the
final vertical error (m) of each flight, then per profile the mean error and its ratio to
the `standard` mean over the flights that have both.
"""
import json
import os
import re
import statistics
import sys

NAME = re.compile(r"^(?P<profile>[A-Za-z0-9_]+)-(?P<seed>\d+)-(?P<run>standard|realistic-\w+|exact_heading-\w+)$")


def load(directory):
    runs = {}  # run -> {(profile, seed): metrics}
    for entry in sorted(os.listdir(directory)):
        m = NAME.match(entry)
        path = os.path.join(directory, entry, "metrics.json")
        if not m or not os.path.isfile(path):
            continue
        with open(path) as f:
            runs.setdefault(m["run"], {})[(m["profile"], int(m["seed"]))] = json.load(f)
    return runs


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    here = os.path.dirname(os.path.abspath(__file__))
    directory = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "logs", "realistic_gap")
    runs = load(directory)
    if "standard" not in runs:
        print(f"realistic_gap_summary: error: no PROFILE-SEED-standard run in {directory}", file=sys.stderr)
        return 1
    kinds = ["standard"] + sorted(k for k in runs if k != "standard")
    flights = sorted(set().union(*(set(r) for r in runs.values())))
    print("| flight | " + " | ".join(f"{k}: % (vertical m)" for k in kinds) + " |")
    print("|---|" + "---|" * len(kinds))
    for fl in flights:
        cells = []
        for k in kinds:
            m = runs[k].get(fl)
            cells.append(f"{m['error_pct_3d']:.4f} ({m['final_error_v_m']:+.2f})" if m else "")
        print(f"| {fl[0]}-{fl[1]} | " + " | ".join(cells) + " |")
    print()
    print("| profile | run | flights | mean error % | mean \\|vertical\\| (m) | ratio to `standard` |")
    print("|---|---|---|---|---|---|")
    for profile in sorted({p for p, _ in flights}):
        for k in kinds:
            both = [fl for fl in runs[k] if fl[0] == profile and fl in runs["standard"]]
            if not both:
                continue
            mean = statistics.mean(runs[k][fl]["error_pct_3d"] for fl in both)
            vert = statistics.mean(abs(runs[k][fl]["final_error_v_m"]) for fl in both)
            std = statistics.mean(runs["standard"][fl]["error_pct_3d"] for fl in both)
            print(f"| {profile} | {k} | {len(both)} | {mean:.4f} | {vert:.2f} | {mean / std:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
