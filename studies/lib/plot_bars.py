#!/usr/bin/python3
"""Grouped bar chart of metrics from several nadir_eval folders.
Usage: plot_bars.py --out PNG --title T --metrics K1,K2 --labels "L1,L2" NAME=DIR [NAME=DIR ...]"""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True)
    p.add_argument("--title", default="")
    p.add_argument("--metrics", required=True, help="comma-separated metrics.json keys")
    p.add_argument("--labels", help="comma-separated legend labels, one per metric")
    p.add_argument("cases", nargs="+", help="NAME=DIR with DIR/metrics.json")
    a = p.parse_args()
    a.metrics = a.metrics.split(",")
    labels = a.labels.split(",") if a.labels else a.metrics
    names, values = [], []
    for case in a.cases:
        name, folder = case.split("=", 1)
        with open(f"{folder}/metrics.json") as f:
            m = json.load(f)
        names.append(name)
        values.append([abs(m[k]) for k in a.metrics])
    width = 0.8 / len(a.metrics)
    fig, ax = plt.subplots(figsize=(1.8 * len(names) + 2, 4))
    for j, label in enumerate(labels):
        xs = [i + (j - (len(a.metrics) - 1) / 2) * width for i in range(len(names))]
        bars = ax.bar(xs, [v[j] for v in values], width, label=label)
        ax.bar_label(bars, fmt="%.2f", fontsize=8)
    ax.set_xticks(range(len(names)), names)
    ax.set_ylabel("% of distance flown")
    ax.set_title(a.title)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
