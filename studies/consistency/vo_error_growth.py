#!/usr/bin/python3
"""How the VO's own translation error grows with the distance flown.

Usage: vo_error_growth.py [--json] [--min-m M] [--plot PNG] DIR [DIR ...]

Each DIR holds one folder per flight with nadir_eval's pairs.csv (a
campaign's cells, or eval folders); flights are grouped by the name's part
before the first '_' or '-' (the profile). Each pair's error is split along
and across its true step, in the pair's own level frame: the heading the
pair is registered with (yaw fusion's business) is not in it. Summed over
every window of consecutive solved pairs, the error of a stretch of D metres
has a spread that the model error of vo_solver.uncertainty says grows as
walk * sqrt(D) (feature_depth_walk_{along,across}_m_per_sqrt_m, 0.006 and
0.002, for the default variant; the one-plane variants' relief_walk_* are
0.068 and 0.012). The levelling errors telescope (each window keeps only its two
end frames'), so past a few hundred metres their part is a constant, and the
slope of the variance against D is the walk squared: fitted here by least
squares over windows of --min-m (500 m) and more, per flight and per group.

Prints the rms of the summed error at 10 m to 5 km against the configured
walk, and the fitted walks; --plot draws the rms against the window per
group, along and across, with the configured walks and paper's."""
import csv
import json
import math
import sys

import numpy as np

from flight_files import flight_files

DISTANCES_M = (10, 30, 100, 300, 1000, 2000, 5000)
WALK_ALONG, WALK_ACROSS = 0.006, 0.002


def load_pairs(path):
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["solved"] == "1"]
    tx = np.array([float(r["true_x"]) for r in rows])
    ty = np.array([float(r["true_y"]) for r in rows])
    dx = np.array([float(r["dx"]) for r in rows])
    dy = np.array([float(r["dy"]) for r in rows])
    step = np.hypot(tx, ty)
    keep = step > 1e-3
    tx, ty, dx, dy, step = tx[keep], ty[keep], dx[keep], dy[keep], step[keep]
    ux, uy = tx / step, ty / step
    along = (dx - tx) * ux + (dy - ty) * uy
    across = -(dx - tx) * uy + (dy - ty) * ux
    return step, along, across


def window_stats(step, along, across, distances):
    """Per distance: (mean window length, mean square along, mean square across) over all windows."""
    c_d = np.concatenate([[0.0], np.cumsum(step)])
    c_a = np.concatenate([[0.0], np.cumsum(along)])
    c_c = np.concatenate([[0.0], np.cumsum(across)])
    out = {}
    for d in distances:
        # every start index, the end index where the window first reaches d metres
        end = np.searchsorted(c_d, c_d + d)
        ok = end < len(c_d)
        if ok.sum() < 10:
            continue
        start, end = np.nonzero(ok)[0], end[ok]
        out[d] = (float((c_d[end] - c_d[start]).mean()), float(((c_a[end] - c_a[start]) ** 2).mean()),
                  float(((c_c[end] - c_c[start]) ** 2).mean()))
    return out


def fit_walk(stats, min_m):
    """Least-squares slope of mean square error against distance for windows >= min_m: walk^2."""
    points = [(v[0], v[1], v[2]) for d, v in stats.items() if d >= min_m]
    if len(points) < 2:
        return None, None
    d = np.array([p[0] for p in points])
    walks = []
    for column in (1, 2):
        y = np.array([p[column] for p in points])
        slope = np.polyfit(d, y, 1)[0]
        walks.append(math.sqrt(max(slope, 0.0)))
    return walks[0], walks[1]


def plot(summary, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
    for ax, column, title, walks in ((axes[0], 1, "along the step", (WALK_ALONG, 0.068)),
                                     (axes[1], 2, "across the step", (WALK_ACROSS, 0.012))):
        for group, s in summary.items():
            d = sorted(s["pooled"])
            ax.loglog([s["pooled"][k][0] for k in d], [math.sqrt(s["pooled"][k][column]) for k in d],
                      marker="o", ms=3, label=f"{group} ({s['flights']} flights)")
        x = np.geomspace(10, 8000, 50)
        ax.loglog(x, walks[0] * np.sqrt(x), "k--", lw=1, label=f"feature_depth walk {walks[0]} m/√m")
        ax.loglog(x, walks[1] * np.sqrt(x), "k:", lw=1, label=f"paper's walk {walks[1]} m/√m")
        ax.set_title(f"summed VO error {title}", fontsize=10)
        ax.set_xlabel("window [m flown]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("rms over all windows [m]")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv):
    as_json = "--json" in argv
    argv = [a for a in argv if a != "--json"]
    png = None
    if "--plot" in argv:
        i = argv.index("--plot")
        if i + 1 >= len(argv):
            raise SystemExit("vo_error_growth: error: --plot needs a PNG path")
        png = argv[i + 1]
        del argv[i:i + 2]
    min_m = 500.0
    if "--min-m" in argv:
        i = argv.index("--min-m")
        if i + 1 >= len(argv):
            raise SystemExit("vo_error_growth: error: --min-m needs metres")
        min_m = float(argv[i + 1])
        del argv[i:i + 2]
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    fit_distances = sorted(set(DISTANCES_M) | {int(x) for x in np.geomspace(min_m, 8000, 12)})
    flights, groups = [], {}
    for name, path in flight_files(argv, "pairs.csv", "vo_error_growth"):
        step, along, across = load_pairs(path)
        stats = window_stats(step, along, across, fit_distances)
        walk = fit_walk(stats, min_m)
        group = name.replace("-", "_").split("_")[0]
        if group == "rough":
            group = "_".join(name.replace("-", "_").split("_")[:2])
        flights.append({"flight": name, "group": group, "distance_m": float(step.sum()),
                        "stats": stats, "walk_along": walk[0], "walk_across": walk[1]})
        groups.setdefault(group, []).append(flights[-1])
    if not flights:
        raise SystemExit("vo_error_growth: error: no <flight>/pairs.csv under " + " ".join(argv))
    summary = {}
    for group, members in groups.items():
        pooled = {}
        for d in fit_distances:
            have = [f["stats"][d] for f in members if d in f["stats"]]
            if have:
                pooled[d] = tuple(float(np.mean([h[i] for h in have])) for i in range(3))
        walk = fit_walk(pooled, min_m)
        summary[group] = {"flights": len(members), "pooled": pooled, "walk_along": walk[0], "walk_across": walk[1]}
    if png:
        plot(summary, png)
    if as_json:
        print(json.dumps({"flights": flights, "groups": summary, "min_m": min_m}, indent=1))
        return 0
    for group, s in summary.items():
        print(f"{group}: {s['flights']} flights; rms of the summed VO error, along / across (configured walk)")
        for d in DISTANCES_M:
            if d in s["pooled"]:
                length, ms_a, ms_c = s["pooled"][d]
                print(f"  {length:7.0f} m: {math.sqrt(ms_a):6.3f} / {math.sqrt(ms_c):6.3f} m "
                      f"({WALK_ALONG * math.sqrt(length):6.3f} / {WALK_ACROSS * math.sqrt(length):6.3f})")
        fmt = lambda w: "-" if w is None else f"{w:.4f}"
        print(f"  walk fitted over windows >= {min_m:.0f} m: along {fmt(s['walk_along'])}, "
              f"across {fmt(s['walk_across'])} m/sqrt(m) (configured {WALK_ALONG} / {WALK_ACROSS}); per flight: "
              + ", ".join(f"{fmt(f['walk_along'])}/{fmt(f['walk_across'])}" for f in flights if f["group"] == group))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
