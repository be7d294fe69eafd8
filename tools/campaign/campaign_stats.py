"""Statistics over a campaign's results: per profile, sensor set and variant,
mean / median / 95th percentile of each metric with bootstrap confidence
intervals (fixed seed: the same results give the same numbers), the count of
diverged flights, and the cells that are missing."""
import math

import numpy as np

DIVERGENCE_METRIC = "error_pct_3d"


def group_key(cell):
    return (cell["profile"], cell["sensor_set"], cell["variant"])


def diverged(metrics, threshold_pct):
    """A flight diverged when it ended farther off than the threshold (percent of distance flown),
    or gave no finite error at all."""
    v = metrics.get(DIVERGENCE_METRIC)
    return metrics.get("poses", 0) == 0 or v is None or not math.isfinite(v) or v > threshold_pct


def bootstrap_ci(values, statistic, samples, seed, confidence):
    """[low, high] of statistic(resample, axis=1) over `samples` resamples of values' first
    axis with replacement (rows stay whole: a row can hold paired values); a fixed
    generator seed, so the same values give the same interval."""
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, len(values), size=(samples, len(values)))
    stats = statistic(values[draws], axis=1)
    tail = 100.0 * (1.0 - confidence) / 2.0
    return [float(np.percentile(stats, tail)), float(np.percentile(stats, 100.0 - tail))]


def summarize(values, evaluate):
    """n, mean, median, p95, and bootstrap intervals of the mean and the median."""
    v = np.array([x for x in values if x is not None and math.isfinite(x)], dtype=float)
    if v.size == 0:
        return {"n": 0}
    args = (evaluate["bootstrap_samples"], evaluate["bootstrap_seed"], evaluate["confidence"])
    return {"n": int(v.size), "mean": float(np.mean(v)), "median": float(np.median(v)),
            "p95": float(np.percentile(v, 95)), "min": float(np.min(v)), "max": float(np.max(v)),
            "mean_ci": bootstrap_ci(v, np.mean, *args), "median_ci": bootstrap_ci(v, np.median, *args)}


def aggregate(spec, results, problems):
    """results: {cell id: result record}; problems: {cell id: (state, log path or None)}.
    Returns the machine-readable aggregate (no times, hosts or paths in its groups:
    the same results aggregate to the same numbers wherever they ran)."""
    ev = spec.evaluate
    groups = {}
    for cell in spec.cells:
        g = groups.setdefault(group_key(cell), {"cells": 0, "values": {m: [] for m in ev["metrics"]},
                                               "diverged": [], "missing": []})
        g["cells"] += 1
        if cell["id"] not in results:
            g["missing"].append(cell["id"])
            continue
        metrics = results[cell["id"]]["metrics"]
        if diverged(metrics, ev["divergence_error_pct"]):
            g["diverged"].append(cell["id"])
        for m in ev["metrics"]:
            g["values"][m].append(metrics.get(m))
    out = []
    for (profile, sensor_set, variant), g in groups.items():
        out.append({"profile": profile, "sensor_set": sensor_set, "variant": variant, "cells": g["cells"],
                    "flights": g["cells"] - len(g["missing"]), "diverged": len(g["diverged"]),
                    "diverged_cells": g["diverged"], "missing_cells": g["missing"],
                    "metrics": {m: summarize(vals, ev) for m, vals in g["values"].items()},
                    "values": g["values"]})
    return {"campaign": spec.name, "evaluate": ev, "groups": out,
            "missing": [{"cell": c, "state": s, "log": log} for c, (s, log) in sorted(problems.items())]}


def _fmt(x):
    return f"{x:.3f}"


METRIC_LABELS = {"error_pct_3d": "final error %", "rms_error_pct_3d": "RMS error %",
                 "error_pct_h": "final horizontal %", "error_pct_v": "final vertical %",
                 "final_error_3d_m": "final error m", "rms_error_3d_m": "RMS error m",
                 "rms_yaw_error_deg": "RMS yaw error deg",
                 # Consistency of the reported covariance (nadir_eval): a consistent
                 # estimator gives mean NEES 2 (horizontal) / 1 (yaw), 95 % within.
                 "nees_h_mean": "horizontal NEES mean", "nees_h_within_95_pct": "horizontal NEES % within 95 % bound",
                 "nees_yaw_mean": "yaw NEES mean", "nees_yaw_within_95_pct": "yaw NEES % within 95 % bound"}


def table(agg):
    """A Markdown table: one row per group; mean [CI], median, p95 per metric."""
    ev = agg["evaluate"]
    ci = f"{round(100 * ev['confidence'])}% CI"
    head = ["profile", "sensor set", "variant", "flights", f"diverged (>{ev['divergence_error_pct']:g} %)"]
    for m in ev["metrics"]:
        label = METRIC_LABELS[m]
        head += [f"{label} mean [{ci}]", f"{label} median", f"{label} p95"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for g in agg["groups"]:
        flights = f"{g['flights']}/{g['cells']}"
        row = [g["profile"], g["sensor_set"], g["variant"], flights, str(g["diverged"])]
        for m in ev["metrics"]:
            s = g["metrics"][m]
            if s["n"] == 0:
                row += ["–", "–", "–"]
                continue
            row += [f"{_fmt(s['mean'])} [{_fmt(s['mean_ci'][0])}, {_fmt(s['mean_ci'][1])}]", _fmt(s["median"]),
                    _fmt(s["p95"])]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"
