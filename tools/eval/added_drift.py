#!/usr/bin/python3
"""Drift that an added sensor noise causes, isolated by pairing runs.

Each case is the same simulated flight (same seed: same terrain, images and
base noise draws) as the reference, with one noise larger. The difference of
the two estimates at each frame time is what the added noise did, free of the
errors both runs share. Prints, per case, the added horizontal and vertical
error at each quarter of the distance flown and the growth ratio (mean added
horizontal error over the last quarter / over the first quarter: about 1 for
a bounded error, above 1 for one that grows with distance), writes them as
JSON, and plots added error against distance flown.

Usage: added_drift.py --reference DIR --out-png PNG --out-json JSON NAME=DIR [NAME=DIR ...]
(each DIR holds the series.csv that nadir_eval writes)"""
import argparse
import csv
import json
import math
import sys

import matplotlib

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
    total = series[-1][0]
    at = []
    for q in (0.25, 0.5, 0.75, 1.0):
        row = min(series, key=lambda s: abs(s[0] - q * total))
        at.append({"fraction": q, "distance_m": row[0], "horizontal_m": row[1], "vertical_m": row[2]})

    def mean_h(lo, hi):
        values = [s[1] for s in series if lo * total <= s[0] <= hi * total]
        return sum(values) / len(values) if values else float("nan")

    first, last = mean_h(0.0, 0.25), mean_h(0.75, 1.0)
    return {"distance_m": total, "at_quarters": at, "mean_h_first_quarter_m": first,
            "mean_h_last_quarter_m": last, "growth_ratio_h": last / first if first > 0 else float("inf")}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--reference", required=True, help="eval folder of the run without the added noise")
    p.add_argument("--out-png", required=True)
    p.add_argument("--out-json", required=True)
    p.add_argument("--title", default="Error added by each noise (paired with the same flight without it)")
    p.add_argument("cases", nargs="+", help="NAME=DIR")
    a = p.parse_args()
    reference = read_series(a.reference)
    results = {}
    fig, (ax_h, ax_v) = plt.subplots(1, 2, figsize=(12, 4.5))
    for case in a.cases:
        if "=" not in case:
            print(f"added_drift: error: case '{case}' is not NAME=DIR", file=sys.stderr)
            return 2
        name, folder = case.split("=", 1)
        series = added_error(reference, read_series(folder))
        if len(series) < 8:
            print(f"added_drift: error: {folder}: fewer than 8 frame times shared with {a.reference}",
                  file=sys.stderr)
            return 1
        results[name] = quarter_summary(series)
        km = [s[0] / 1000 for s in series]
        ax_h.plot(km, [s[1] for s in series], label=name, lw=1)
        ax_v.plot(km, [abs(s[2]) for s in series], label=name, lw=1)
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
    print("| added noise | added horizontal error at 1/4, 1/2, 3/4, end of distance (m) | growth ratio"
          " (last / first quarter) | added vertical error at end (m) |")
    print("|---|---|---|---|")
    for name, r in results.items():
        quarters = ", ".join(f"{q['horizontal_m']:.1f}" for q in r["at_quarters"])
        print(f"| {name} | {quarters} | {r['growth_ratio_h']:.1f} | {r['at_quarters'][-1]['vertical_m']:.1f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
