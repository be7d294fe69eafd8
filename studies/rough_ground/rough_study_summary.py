#!/usr/bin/python3
"""Summary of rough-ground studies (rough_study.sh): per profile and variant, each
seed's final error over relief and over flat ground and their ratio; over all the
seeds, the ratio of the mean errors with a bootstrap interval (the seeds resampled
with their two flights together; a fixed generator seed, so the same rows give the
same interval), the median of the per-seed ratios, the flights within the goal's
ratio, and the ratio of the means over each run of three seeds in seed order.

Several rows.csv files (studies run apart, on other seeds) are pooled; a flight
given twice must agree. Writes summary.json and summary.csv into --out."""
import argparse
import csv
import itertools
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "tools", "campaign"))
from campaign_stats import bootstrap_ci  # noqa: E402

GROUP = 3  # the goal is over three seeds
COLUMNS = ("profile", "seed", "ground", "variant", "final_error_pct")


def read_rows(paths):
    """{(profile, seed, ground, variant): final error %}; raises ValueError naming the file and line."""
    err = {}
    for path in paths:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in COLUMNS if c not in (reader.fieldnames or [])]
            if missing:
                raise ValueError(f"{path}: no column {', '.join(missing)}")
            for line, r in enumerate(reader, start=2):
                try:
                    key = (r["profile"], int(r["seed"]), r["ground"], r["variant"])
                    value = float(r["final_error_pct"])
                except (TypeError, ValueError):
                    raise ValueError(f"{path}:{line}: bad seed or final_error_pct") from None
                if key[2] not in ("rough", "flat") or not math.isfinite(value) or value < 0:
                    raise ValueError(f"{path}:{line}: ground must be rough or flat, the error a finite % >= 0")
                if key in err and err[key] != value:
                    raise ValueError(f"{path}:{line}: {key} given twice, {err[key]} and {value}")
                err[key] = value
    return err


def ratio_of_means(pairs, axis):
    """pairs[..., 0] rough, pairs[..., 1] flat: mean rough over mean flat along axis."""
    m = np.mean(pairs, axis=axis)
    return m[..., 0] / m[..., 1]


def summarize(err, goal, confidence, samples):
    groups = sorted({(k[0], k[3]) for k in err})
    per_seed, overall = [], []
    for p, v in groups:
        seeds = sorted(s for (pp, s, g, vv) in err if pp == p and vv == v and g == "rough" and (p, s, "flat", v) in err)
        if not seeds:
            continue
        pairs = np.array([[err[(p, s, "rough", v)], err[(p, s, "flat", v)]] for s in seeds])
        ratios = [float(r / f) if f > 0 else math.inf for r, f in pairs]
        for s, (r, f), q in zip(seeds, pairs, ratios):
            per_seed.append({"profile": p, "variant": v, "seed": s, "rough_error_pct": float(r),
                             "flat_error_pct": float(f), "ratio": q})
        runs = []
        for i in range(0, len(seeds) - GROUP + 1, GROUP):
            runs.append({"seeds": seeds[i:i + GROUP], "ratio": float(ratio_of_means(pairs[i:i + GROUP], 0))})
        overall.append({
            "profile": p, "variant": v, "seeds": seeds, "mean_rough_pct": float(pairs[:, 0].mean()),
            "mean_flat_pct": float(pairs[:, 1].mean()), "ratio_of_means": float(ratio_of_means(pairs, 0)),
            "ratio_interval": bootstrap_ci(pairs, ratio_of_means, samples, 0, confidence) if len(seeds) > 1 else None,
            "confidence": confidence, "median_ratio": float(np.median(ratios)),
            "flights_within_goal": int(sum(q <= goal for q in ratios)), "goal": goal, "three_seed_runs": runs,
            "three_seed_runs_within_goal": int(sum(r["ratio"] <= goal for r in runs))})
    return per_seed, overall


def seed_list(seeds):
    """1, 2, 3, 5 -> '1–3, 5' (consecutive seeds share seed - position)."""
    parts = []
    for _, run in itertools.groupby(enumerate(seeds), key=lambda t: t[1] - t[0]):
        run = [s for _, s in run]
        parts.append(f"{run[0]}–{run[-1]}" if len(run) > 1 else f"{run[0]}")
    return ", ".join(parts)


def markdown(per_seed, overall):
    lines = ["| profile | variant | seed | rough: final error % | flat: final error % | rough / flat |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {r['profile']} | {r['variant']} | {r['seed']} | {r['rough_error_pct']:.4f} | "
              f"{r['flat_error_pct']:.4f} | {r['ratio']:.2f} |" for r in per_seed]
    lines += ["", "| profile | variant | seeds | mean rough % | mean flat % | ratio of the means "
              "[interval] | median ratio | flights within | three-seed runs within |", "|---|---|---|---|---|---|---|---|---|"]
    for o in overall:
        ci = o["ratio_interval"]
        interval = f" [{ci[0]:.2f}, {ci[1]:.2f}]" if ci else ""
        runs = ", ".join(f"{seed_list(r['seeds'])}: {r['ratio']:.2f}" for r in o["three_seed_runs"])
        within_runs = f"{o['three_seed_runs_within_goal']}/{len(o['three_seed_runs'])} ({runs})" if runs else "–"
        lines.append(f"| {o['profile']} | {o['variant']} | {len(o['seeds'])} ({seed_list(o['seeds'])}) | "
                     f"{o['mean_rough_pct']:.4f} | "
                     f"{o['mean_flat_pct']:.4f} | **{o['ratio_of_means']:.2f}**{interval} | {o['median_ratio']:.2f} | "
                     f"{o['flights_within_goal']}/{len(o['seeds'])} | "
                     f"{within_runs} |")
    if overall:
        o = overall[0]
        lines.append(f"\n(interval: {round(100 * o['confidence'])} % bootstrap over the seeds; "
                     f"within: rough / flat <= {o['goal']:g})")
    return "\n".join(lines)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("rows", nargs="+", help="rows.csv of rough_study.sh runs (profile,seed,ground,variant,"
                                            "final_error_pct,...)")
    ap.add_argument("--out", required=True, help="folder for summary.json and summary.csv")
    ap.add_argument("--goal", type=float, default=1.5, help="the ratio a flight or run must stay within (1.5)")
    ap.add_argument("--confidence", type=float, default=0.9, help="of the bootstrap interval (0.9)")
    ap.add_argument("--samples", type=int, default=10000, help="bootstrap resamples (10000)")
    a = ap.parse_args(argv)
    if not (a.goal > 0 and 0 < a.confidence < 1 and a.samples >= 100):
        ap.error("--goal must be > 0, --confidence in (0, 1), --samples >= 100")
    try:
        err = read_rows(a.rows)
    except (OSError, ValueError) as e:
        print(f"rough_study_summary: error: {e}", file=sys.stderr)
        return 2
    per_seed, overall = summarize(err, a.goal, a.confidence, a.samples)
    if not overall:
        print("rough_study_summary: error: no seed has both a rough and a flat flight", file=sys.stderr)
        return 2
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump({"per_seed": per_seed, "overall": overall}, f, indent=1)
    with open(os.path.join(a.out, "summary.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["profile", "variant", "seed", "rough_error_pct", "flat_error_pct", "ratio"])
        w.writeheader()
        w.writerows(per_seed)
    print(markdown(per_seed, overall))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
