#!/usr/bin/python3
"""Drift that an added sensor noise causes, isolated by pairing runs.

Each case is the same simulated flight (same seed: same terrain, images and
base noise draws) as the reference, with one noise larger. The difference of
the two estimates at each frame time is what the added noise did, free of the
errors both runs share. Prints, per case, the mean added horizontal error over
each quarter of the distance flown, the added vertical error at the end and
the growth ratio (mean added
horizontal error over the last quarter / over the first quarter: about 1 for
a bounded error, above 1 for one that grows with distance), writes them as
JSON, and plots added error against distance flown.

With several seeds, repeat --reference (one per seed) and give each case one
DIR per reference: the quarter means are averaged over the flights.

Usage: added_drift.py --reference DIR [--reference DIR ...] --out-png PNG --out-json JSON
                      NAME=DIR[,DIR...] [NAME=DIR[,DIR...] ...]
(each DIR holds the series.csv that nadir_eval writes)"""
import argparse
import csv
import json
import math
import sys

import matplotlib
import numpy

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_series(folder):
    path = f"{folder}/series.csv"
    rows = {}
    try:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                key = round(float(row["t_s"]) * 1000)  # frame times in ms: identical in paired runs
                rows[key] = (float(row["distance_m"]),
                             (float(row["est_n"]), float(row["est_e"]), float(row["est_d"])))
    except (OSError, KeyError, ValueError) as e:
        raise SystemExit(f"added_drift: error: {path}: {e}")
    if not rows:
        raise SystemExit(f"added_drift: error: {path}: no rows")
    return rows


def added_error(reference, case):
    """(distance, horizontal, vertical) of case - reference at the frame times both have."""
    out = []
    for key in sorted(set(reference) & set(case)):
        distance, ref = reference[key]
        _, est = case[key]
        dn, de, dd = (est[i] - ref[i] for i in range(3))
        out.append((distance, math.hypot(dn, de), -dd))
    return out


def quarter_summary(series):
    """Mean added error over each quarter of the distance (per-frame values of a
    bounded error jump around; their mean per stretch shows whether it grows)."""
    total = series[-1][0]

    def mean(index, lo, hi):
        values = [abs(s[index]) for s in series if lo * total <= s[0] <= hi * total]
        return sum(values) / len(values) if values else float("nan")

    quarters = [{"from": q / 4, "to": (q + 1) / 4, "mean_horizontal_m": mean(1, q / 4, (q + 1) / 4),
                 "mean_vertical_m": mean(2, q / 4, (q + 1) / 4)} for q in range(4)]
    first, last = quarters[0]["mean_horizontal_m"], quarters[-1]["mean_horizontal_m"]
    return {"distance_m": total, "quarters": quarters, "end_horizontal_m": series[-1][1],
            "end_vertical_m": series[-1][2], "growth_ratio_h": last / first if first > 0 else float("inf")}


def running_mean(values, width):
    out, acc = [], 0.0
    for i, v in enumerate(values):
        acc += v
        if i >= width:
            acc -= values[i - width]
        out.append(acc / min(i + 1, width))
    return out


def mean_summary(summaries):
    """Per-quarter means averaged over flights (seeds); growth from the averages."""
    n = len(summaries)
    quarters = [{"from": q["from"], "to": q["to"],
                 "mean_horizontal_m": sum(s["quarters"][i]["mean_horizontal_m"] for s in summaries) / n,
                 "mean_vertical_m": sum(s["quarters"][i]["mean_vertical_m"] for s in summaries) / n}
                for i, q in enumerate(summaries[0]["quarters"])]
    first, last = quarters[0]["mean_horizontal_m"], quarters[-1]["mean_horizontal_m"]
    return {"flights": n, "per_flight": summaries, "quarters": quarters,
            "end_vertical_m": sum(abs(s["end_vertical_m"]) for s in summaries) / n,
            "growth_ratio_h": last / first if first > 0 else float("inf")}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--reference", required=True, action="append",
                   help="eval folder of the run without the added noise; repeat it for more seeds")
    p.add_argument("--out-png", required=True)
    p.add_argument("--out-json", required=True)
    p.add_argument("--title", default="Error added by each noise (paired with the same flight without it)")
    p.add_argument("cases", nargs="+", help="NAME=DIR[,DIR...]: one DIR per --reference, in the same order")
    a = p.parse_args()
    references = [read_series(r) for r in a.reference]
    results = {}
    fig, (ax_h, ax_v) = plt.subplots(1, 2, figsize=(12, 4.5))
    for case in a.cases:
        name, _, folders = case.partition("=")
        folders = folders.split(",") if folders else []
        if len(folders) != len(references):
            print(f"added_drift: error: case '{case}' needs NAME= and {len(references)} folder(s), one per "
                  "--reference", file=sys.stderr)
            return 2
        summaries, curves = [], []
        for reference_dir, reference, folder in zip(a.reference, references, folders):
            series = added_error(reference, read_series(folder))
            if len(series) < 8:
                print(f"added_drift: error: {folder}: fewer than 8 frame times shared with {reference_dir}",
                      file=sys.stderr)
                return 1
            summaries.append(quarter_summary(series))
            curves.append(series)
        results[name] = mean_summary(summaries)
        # The first flight drawn as measured; the 10 s mean over all flights on
        # a common distance axis.
        total = min(c[-1][0] for c in curves)
        grid = [total * i / 400 for i in range(401)]
        for ax, index in ((ax_h, 1), (ax_v, 2)):
            values = [abs(s[index]) for s in curves[0]]
            line, = ax.plot([s[0] / 1000 for s in curves[0]], values, lw=0.5, alpha=0.25)
            smoothed = [numpy.interp(grid, [s[0] for s in c], running_mean([abs(s[index]) for s in c], 140))
                        for c in curves]
            ax.plot([g / 1000 for g in grid], numpy.mean(smoothed, axis=0), lw=2, color=line.get_color(),
                    label=f"{name} (10 s mean{f', {len(curves)} flights' if len(curves) > 1 else ''})")
    for ax, what in ((ax_h, "horizontal"), (ax_v, "vertical")):
        ax.set_xlabel("distance flown (km)")
        ax.set_ylabel(f"added {what} error (m)")
        ax.grid(True, alpha=0.3)
        ax.legend()
    ax_v.set_yscale("log")
    fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.out_png, dpi=110)
    with open(a.out_json, "w") as f:
        json.dump(results, f, indent=1)
    flights = f" (mean of {len(references)} flights)" if len(references) > 1 else ""
    print(f"| added noise | mean added horizontal error per quarter of the distance (m){flights} | growth ratio"
          " (last / first quarter) | added vertical error at the end (m) |")
    print("|---|---|---|---|")
    for name, r in results.items():
        quarters = ", ".join(f"{q['mean_horizontal_m']:.1f}" for q in r["quarters"])
        print(f"| {name} | {quarters} | {r['growth_ratio_h']:.1f} | {r['end_vertical_m']:.1f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
