#!/usr/bin/python3
"""Plots an evaluation folder written by nadir_eval: trajectory.png (top view,
estimate vs truth, start marked), drift.png (Fig. 7a), velocity_errors.png
(Fig. 7b). Usage: plot_eval.py DIR"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) == 2 else 2
    folder = sys.argv[1]
    with open(f"{folder}/series.csv", newline="") as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    with open(f"{folder}/metrics.json") as f:
        m = json.load(f)
    if not rows:
        print(f"plot_eval: {folder}/series.csv has no rows", file=sys.stderr)
        return 1
    col = lambda k: [r[k] for r in rows]  # noqa: E731
    title = (f"{m['distance_m']:.0f} m flown, final error {m['final_error_3d_m']:.1f} m "
             f"({m['error_pct_3d']:.2f} % of distance)")

    fig, ax = plt.subplots(figsize=(7, 7))
    ax.plot(col("true_e"), col("true_n"), color="tab:red", lw=2, label="ground truth")
    ax.plot(col("est_e"), col("est_n"), color="tab:blue", lw=1.5, label="nadir estimate")
    ax.plot([0], [0], "ko", ms=8, label="start")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(f"{folder}/trajectory.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(col("t_s"), col("error_h_m"), label="horizontal")
    ax.plot(col("t_s"), [abs(v) for v in col("error_v_m")], label="vertical")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("accumulated position drift [m]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(f"{folder}/drift.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 4))
    for k, name in (("vel_err_n", "north"), ("vel_err_e", "east"), ("vel_err_d", "down")):
        ax.plot(col("t_s"), [abs(v) for v in col(k)], lw=0.8, label=name)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("absolute velocity error [m/s]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(f"{folder}/velocity_errors.png", dpi=110)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
