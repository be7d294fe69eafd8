#!/usr/bin/python3
"""Consistency of the reported covariance over many evaluated flights.

Usage: consistency_table.py [--json] [--plot PNG] NAME=DIR [NAME=DIR ...]

Each DIR holds one folder per flight with nadir_eval's series.csv, or its
eval/series.csv (a campaign's cells folder, or replays of cached simulator
logs). Per set:

- final pose: the NEES of each flight's last pose; over N independent flights
  N * mean is chi-square with N * dim degrees of freedom, so the mean has the
  95 % interval [chi2(2.5 %), chi2(97.5 %)] / N (dim 2 horizontal, 1 yaw);
- every pose: the NEES averaged over the flights at each time (the Monte Carlo
  test of Bar-Shalom et al.), the share of those time steps whose average is
  inside the same interval, and the share of single poses within the per-pose
  95 % bound (5.991 / 3.841);
- protection level: share of poses whose horizontal error exceeded it, and
  the 99th percentile of the levels over that of the errors (how wide it is);
- the share of flights whose final NEES is inside the two-sided 95 % band of
  chi-square(2), 0.05-7.38.
--plot draws the flights' horizontal error over the reported 3 sigma and the
average NEES against its interval."""
import csv
import json
import math
import sys

from scipy.stats import chi2

from flight_files import flight_files


def load(folder):
    flights = []
    for name, path in flight_files([folder], "series.csv", "consistency_table"):
        with open(path) as f:
            rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
        rows = [r for r in rows if r["nees_h"] >= 0 and r["nees_yaw"] >= 0]
        if rows:
            flights.append((name, rows))
    if not flights:
        raise SystemExit(f"consistency_table: error: no <flight>/series.csv with NEES under {folder}")
    return flights


def interval(n, dim):
    return float(chi2.ppf(0.025, n * dim) / n), float(chi2.ppf(0.975, n * dim) / n)


def summarise(flights):
    n = len(flights)
    out = {"flights": n}
    for key, dim, bound in (("nees_h", 2, 5.991), ("nees_yaw", 1, 3.841)):
        lo, hi = interval(n, dim)
        final = sum(rows[-1][key] for _, rows in flights) / n
        steps = min(len(rows) for _, rows in flights)
        averages = [sum(rows[i][key] for _, rows in flights) / n for i in range(steps)]
        poses = [r[key] for _, rows in flights for r in rows]
        out[key] = {"final_mean": final, "interval_95": [lo, hi], "final_inside": bool(lo <= final <= hi),
                    "all_poses_mean": sum(poses) / len(poses),
                    "time_steps_inside_pct": 100.0 * sum(lo <= a <= hi for a in averages) / steps,
                    "poses_within_bound_pct": 100.0 * sum(v <= bound for v in poses) / len(poses)}
    pl = [(r["error_h_m"], r["protection_level_m"]) for _, rows in flights for r in rows
          if r.get("protection_level_m", -1) >= 0]
    out["pl_exceeded_pct"] = 100.0 * sum(e > p for e, p in pl) / len(pl) if pl else float("nan")
    out["pl_samples"] = len(pl)
    # One flight's final NEES against the two-sided 95 % band of chi-square(2).
    lo1, hi1 = float(chi2.ppf(0.025, 2)), float(chi2.ppf(0.975, 2))
    out["final_nees_h_in_band_pct"] = 100.0 * sum(lo1 <= rows[-1]["nees_h"] <= hi1 for _, rows in flights) / n
    # How wide the protection level is: the 99th percentile of the levels
    # over the poses against the 99th percentile of their horizontal errors.
    if pl:
        k = min(len(pl) - 1, int(0.99 * len(pl)))
        p99_error, p99_level = sorted(e for e, _ in pl)[k], sorted(p for _, p in pl)[k]
        out["pl_over_error_p99"] = p99_level / p99_error if p99_error > 0 else float("nan")
    else:
        out["pl_over_error_p99"] = float("nan")
    return out


def table(results):
    lines = ["| set | flights | horizontal NEES: final-pose mean (95 % interval) | average over poses | "
             "time steps inside | poses within 5.991 | yaw NEES: final-pose mean (95 % interval) | "
             "average over poses | time steps inside | poses within 3.841 | beyond the 99 % protection level | "
             "flights' final NEES in the 95 % band | protection level / horizontal error, 99th percentiles |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, s in results.items():
        h, y = s["nees_h"], s["nees_yaw"]
        lines.append(
            f"| {name} | {s['flights']} | {h['final_mean']:.2f} ({h['interval_95'][0]:.2f}-{h['interval_95'][1]:.2f}) "
            f"| {h['all_poses_mean']:.2f} | {h['time_steps_inside_pct']:.0f} % | {h['poses_within_bound_pct']:.1f} % "
            f"| {y['final_mean']:.2f} ({y['interval_95'][0]:.2f}-{y['interval_95'][1]:.2f}) | {y['all_poses_mean']:.2f} "
            f"| {y['time_steps_inside_pct']:.0f} % | {y['poses_within_bound_pct']:.1f} % | {s['pl_exceeded_pct']:.2f} % "
            f"| {s['final_nees_h_in_band_pct']:.0f} % | {s['pl_over_error_p99']:.1f} |")
    return "\n".join(lines)


def plot(sets, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, len(sets), figsize=(6 * len(sets), 7), squeeze=False)
    for col, (name, flights) in enumerate(sets.items()):
        ax = axes[0][col]
        for i, (_, rows) in enumerate(flights):
            t = [r["t_s"] for r in rows]
            ax.plot(t, [r["error_h_m"] for r in rows], color="tab:blue", lw=0.6, alpha=0.7,
                    label="horizontal error" if i == 0 else None)
            ax.plot(t, [3 * r["sigma_h_m"] for r in rows], color="tab:green", lw=0.6, alpha=0.7,
                    label="reported 3σ (√(σn²+σe²))" if i == 0 else None)
        ax.set_title(f"{name}: {len(flights)} flights", fontsize=10)
        ax.set_ylabel("m")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
        ax = axes[1][col]
        n = len(flights)
        steps = min(len(rows) for _, rows in flights)
        t = [flights[0][1][i]["t_s"] for i in range(steps)]
        for key, dim, color in (("nees_h", 2, "tab:blue"), ("nees_yaw", 1, "tab:orange")):
            avg = [sum(rows[i][key] for _, rows in flights) / n for i in range(steps)]
            lo, hi = interval(n, dim)
            ax.plot(t, avg, color=color, lw=0.8, label=f"{key} averaged over the flights (dim {dim})")
            ax.axhspan(lo, hi, color=color, alpha=0.15)
        ax.set_yscale("log")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("NEES (bands: 95 % interval)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    as_json = "--json" in argv
    argv = [a for a in argv if a != "--json"]
    png = None
    if "--plot" in argv:
        i = argv.index("--plot")
        png = argv[i + 1]
        del argv[i:i + 2]
    sets = {}
    for arg in argv:
        if "=" not in arg:
            raise SystemExit(f"consistency_table: error: '{arg}' is not NAME=DIR")
        name, folder = arg.split("=", 1)
        sets[name] = load(folder)
    results = {name: summarise(flights) for name, flights in sets.items()}
    print(json.dumps(results, indent=1) if as_json else table(results))
    if png:
        plot(sets, png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
