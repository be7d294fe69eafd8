#!/usr/bin/python3
"""Plots an evaluation folder written by nadir_eval: trajectory.png (top view,
estimate vs truth, start marked), drift.png (Fig. 7a), velocity_errors.png
(Fig. 7b), consistency.png (north/east position and yaw error against the
reported +-3 sigma); the coasts (metrics.json) shaded in drift.png and
consistency.png. Usage: plot_eval.py DIR"""
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
    coasts = m.get("coasts", [])

    def shade_coasts(ax):
        """The coasts (VO out, the position held) as shaded time spans."""
        for i, c in enumerate(coasts):
            ax.axvspan(c["start_s"], c["start_s"] + c["duration_s"], color="tab:gray", alpha=0.3, lw=0,
                       label="coasting" if i == 0 else None)
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
    shade_coasts(ax)
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

    if "sigma_n_m" in rows[0]:
        t = col("t_s")
        has_pl = "protection_level_m" in rows[0]
        fig, axes = plt.subplots(4 if has_pl else 3, 1, figsize=(8, 10.5 if has_pl else 8), sharex=True)
        for ax in axes:
            shade_coasts(ax)
        series = (("north", [r["est_n"] - r["true_n"] for r in rows], col("sigma_n_m"), "m"),
                  ("east", [r["est_e"] - r["true_e"] for r in rows], col("sigma_e_m"), "m"),
                  ("yaw", col("yaw_error_deg"), col("sigma_yaw_deg"), "deg"))
        if has_pl:
            pl = [r["protection_level_m"] if r["protection_level_m"] >= 0 else float("nan") for r in rows]
            axes[3].fill_between(t, 0, pl, color="tab:orange", alpha=0.25, label="protection level (99 %)")
            axes[3].plot(t, col("error_h_m"), color="tab:blue", lw=1, label="horizontal error")
            axes[3].set_ylabel("horizontal [m]")
            axes[3].grid(True, alpha=0.3)
            axes[3].legend(loc="upper left", fontsize=8)
            axes[3].set_title(f"true error above the protection level at {m.get('pl_exceeded_pct', 0):.2f} % "
                              "of the poses (stated: 1 %)", fontsize=9)
        for ax, (name, err, sigma, unit) in zip(axes, series):
            ax.fill_between(t, [-3 * v for v in sigma], [3 * v for v in sigma], color="tab:green", alpha=0.25,
                            label="reported ±3σ")
            ax.plot(t, err, color="tab:blue", lw=1, label=f"{name} error")
            ax.set_ylabel(f"{name} error [{unit}]")
            ax.grid(True, alpha=0.3)
            ax.legend(loc="upper left", fontsize=8)
        axes[-1].set_xlabel("time [s]")
        axes[0].set_title(f"NEES horizontal mean {m.get('nees_h_mean', 0):.1f} (consistent: 2), "
                          f"{m.get('nees_h_within_95_pct', 0):.0f} % within the 95 % bound; yaw mean "
                          f"{m.get('nees_yaw_mean', 0):.1f} (1), {m.get('nees_yaw_within_95_pct', 0):.0f} %",
                          fontsize=9)
        fig.tight_layout()
        fig.savefig(f"{folder}/consistency.png", dpi=110)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
