"""The distribution plot of a campaign: a box plot of each metric per group
(every flight drawn as a dot) and the CDF of the first metric."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402

from campaign_stats import METRIC_LABELS  # noqa: E402


def _label(g):
    return f"{g['profile']}\n{g['sensor_set']}/{g['variant']}"


def plot(agg, png_path, title):
    metrics = agg["evaluate"]["metrics"]
    groups = [g for g in agg["groups"] if g["flights"] > 0]
    fig, axes = plt.subplots(1, len(metrics) + 1, figsize=(4.2 * (len(metrics) + 1), 4.4))
    for ax, m in zip(axes, metrics):
        data = [np.array([v for v in g["values"][m] if v is not None], dtype=float) for g in groups]
        ax.boxplot(data, whis=(5, 95), showfliers=False)
        for i, d in enumerate(data, start=1):
            ax.plot(np.full(d.size, i) + np.linspace(-0.12, 0.12, d.size), d, ".", color="tab:blue", alpha=0.6)
        ax.set_xticks(range(1, len(groups) + 1), [_label(g) for g in groups], fontsize=8)
        ax.set_ylabel(METRIC_LABELS[m])
        ax.set_title(f"{METRIC_LABELS[m]} (whiskers 5-95 %)", fontsize=10)
        ax.grid(axis="y", alpha=0.3)
    ax = axes[-1]
    m = metrics[0]
    for g in groups:
        d = np.sort(np.array([v for v in g["values"][m] if v is not None], dtype=float))
        ax.step(d, np.arange(1, d.size + 1) / d.size, where="post", label=_label(g).replace("\n", " "))
    ax.set_xlabel(METRIC_LABELS[m])
    ax.set_ylabel("share of flights")
    ax.set_title(f"CDF of {METRIC_LABELS[m]}", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    plt.close(fig)
