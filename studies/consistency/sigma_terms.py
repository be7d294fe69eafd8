#!/usr/bin/python3
"""Where the reported horizontal sigma comes from, and what another relief model would report.

Usage: sigma_terms.py [--json] [--walk ALONG ACROSS] [--candidate ALONG ACROSS ANCHOR]
                      [--yaw-bias STDDEV WALK TAU_FLOWN TAU_MODEL] DIR [DIR ...]

Each DIR holds one folder per flight with nadir_eval's series.csv (a
campaign's cells, or eval folders). The relief model error is the one term of
the reported covariance that follows the track alone: vo_solver adds
ALONG^2 * step along each step and ACROSS^2 * step across it
(vo_solver.uncertainty.feature_depth_walk_{along,across}_m_per_sqrt_m for
the default variant; --walk, default its 0.006 0.002 m/sqrt(m); the one-plane
variants' relief_walk_* are 0.068 0.012). It is summed here over the
true track, independently of the estimator; the rest of the reported
covariance (levelling, INS yaw bias, image noise, heading drift) is the
reported one minus it. Without map fixes the position never feeds back into
the estimate, so the rest is exact and a relief model can be swapped offline.

Per flight, at the last pose: the error and the sigma per axis, the relief
and the rest. Over all flights: the final-pose horizontal NEES (2-D when
series.csv has cov_ne_m2, per axis otherwise), the average NEES over all
poses and the share of poses beyond 3.035 times the largest sigma (the 99 %
protection level of a clean flight) for: the reported covariance, the rest
alone, and --candidate: the rest plus a walk ALONG/ACROSS and a per-frame
relief error of ANCHOR m per axis that telescopes (added once, like the
current frame's levelling).

--yaw-bias STDDEV WALK TAU_FLOWN TAU_MODEL: the flights were replayed with the
INS yaw bias as an offset of STDDEV deg (Gauss-Markov of correlation TAU_FLOWN
s; 0: constant) plus a walk of WALK deg/sqrt(s) (yaw_fusion.ins_yaw_bias_*);
model "yaw_bias" swaps that term (summed over the true track as yaw fusion's
consider state does) for the same offset with correlation TAU_MODEL."""
import csv
import json
import math
import sys

from flight_files import flight_files

PROTECTION_FACTOR = 3.035  # 99 % of a 2-D Gaussian, on the largest axis (protection_level.h)


def load(path):
    with open(path) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    rows = [r for r in rows if r["sigma_n_m"] > 0 and r["nees_h"] >= 0]
    if len(rows) < 2:
        raise SystemExit(f"sigma_terms: error: {path}: fewer than two poses with a covariance")
    return rows


def walk_covariances(rows, along, across):
    """Per pose, the (nn, ne, ee) covariance of a relief walk summed over the true track."""
    nn = ne = ee = 0.0
    out = [(0.0, 0.0, 0.0)]
    for a, b in zip(rows, rows[1:]):
        dn, de = b["true_n"] - a["true_n"], b["true_e"] - a["true_e"]
        step = math.hypot(dn, de)
        if step > 0.0:
            un, ue = dn / step, de / step
            va, vc = along**2 * step, across**2 * step
            nn += va * un * un + vc * ue * ue
            ee += va * ue * ue + vc * un * un
            ne += (va - vc) * un * ue
        out.append((nn, ne, ee))
    return out


def yaw_bias_covariances(rows, stddev_deg, walk_deg, tau):
    """Per pose, the (nn, ne, ee) covariance of the INS yaw bias carried into position
    (yaw_fusion's consider state (e_n, e_e, b_walk, b_markov), PoseFilter::add_shared_errors)."""
    s0, w = math.radians(stddev_deg) ** 2, math.radians(walk_deg) ** 2
    c = [[0.0] * 4 for _ in range(4)]
    out = [(0.0, 0.0, 0.0)]
    for i, (a, b) in enumerate(zip(rows, rows[1:])):
        dt = max(b["t_s"] - a["t_s"], 0.0)
        tn, te = b["true_n"] - a["true_n"], b["true_e"] - a["true_e"]
        f = [[1, 0, -te, -te], [0, 1, tn, tn], [0, 0, 1, 0], [0, 0, 0, 1]]
        decay = math.exp(-dt / tau) if tau > 0 else 1.0
        f[3][3] = decay
        fc = [[sum(f[r][k] * c[k][col] for k in range(4)) for col in range(4)] for r in range(4)]
        c = [[sum(fc[r][k] * f[col][k] for k in range(4)) for col in range(4)] for r in range(4)]
        c[2][2] += w * dt
        if tau > 0:
            c[3][3] += s0 * (1.0 if i == 0 else 1.0 - decay * decay)
        elif i == 0:
            c[2][2] += s0
        out.append((c[0][0], c[0][1], c[1][1]))
    return out


def nees(en, ee, cnn, cne, cee):
    det = cnn * cee - cne * cne
    if det <= 1e-12:
        return float("nan")
    return (en * en * cee - 2 * en * ee * cne + ee * ee * cnn) / det


def largest_sigma(cnn, cne, cee):
    half_trace, half_diff = 0.5 * (cnn + cee), 0.5 * (cnn - cee)
    return math.sqrt(max(half_trace + math.hypot(half_diff, cne), 0.0))


def evaluate(rows, covariances):
    """(final NEES, mean NEES over poses, poses beyond the protection level)."""
    values, beyond = [], 0
    for r, (cnn, cne, cee) in zip(rows, covariances):
        en, ee = r["est_n"] - r["true_n"], r["est_e"] - r["true_e"]
        values.append(nees(en, ee, cnn, cne, cee))
        beyond += math.hypot(en, ee) > PROTECTION_FACTOR * largest_sigma(cnn, cne, cee)
    finite = [v for v in values if math.isfinite(v)]
    return values[-1], sum(finite) / max(len(finite), 1), beyond


def flight(name, path, walk, candidate, yaw_bias=None):
    rows = load(path)
    has_cross = "cov_ne_m2" in rows[0]
    reported = [(r["sigma_n_m"] ** 2, r.get("cov_ne_m2", 0.0), r["sigma_e_m"] ** 2) for r in rows]
    relief = walk_covariances(rows, *walk)
    if not has_cross:  # per axis only: drop the walk's cross term too
        relief = [(nn, 0.0, ee) for nn, _, ee in relief]
    floor = 1e-4  # m^2: the rest never below 1 cm
    rest = [(max(p[0] - q[0], floor), p[1] - q[1], max(p[2] - q[2], floor)) for p, q in zip(reported, relief)]
    models = {"reported": reported, "rest": rest}
    if candidate:
        c_walk = walk_covariances(rows, candidate[0], candidate[1])
        if not has_cross:
            c_walk = [(nn, 0.0, ee) for nn, _, ee in c_walk]
        anchor = candidate[2] ** 2
        models["candidate"] = [(p[0] + w[0] + anchor, p[1] + w[1], p[2] + w[2] + anchor) for p, w in zip(rest, c_walk)]
    if yaw_bias:
        flown = yaw_bias_covariances(rows, yaw_bias[0], yaw_bias[1], yaw_bias[2])
        markov = yaw_bias_covariances(rows, yaw_bias[0], yaw_bias[1], yaw_bias[3])
        models["yaw_bias"] = [(max(p[0] - f[0] + m[0], floor), p[1] - f[1] + m[1], max(p[2] - f[2] + m[2], floor))
                            for p, f, m in zip(reported, flown, markov)]
    last = rows[-1]
    out = {"flight": name, "distance_m": last["distance_m"], "poses": len(rows), "nees_2d": has_cross,
           "error_n_m": last["est_n"] - last["true_n"], "error_e_m": last["est_e"] - last["true_e"],
           "sigma_n_m": last["sigma_n_m"], "sigma_e_m": last["sigma_e_m"],
           "relief_sigma_n_m": math.sqrt(relief[-1][0]), "relief_sigma_e_m": math.sqrt(relief[-1][2]),
           "rest_sigma_n_m": math.sqrt(rest[-1][0]), "rest_sigma_e_m": math.sqrt(rest[-1][2])}
    for model, covariances in models.items():
        final, mean, beyond = evaluate(rows, covariances)
        out[model] = {"final_nees": final, "mean_nees": mean, "beyond_pl": beyond}
    return out


def parse(argv):
    options = {"json": False, "walk": (0.006, 0.002), "candidate": None, "yaw_bias": None, "dirs": []}
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        elif a == "--json":
            options["json"] = True
        elif a == "--walk" and i + 2 < len(argv):
            options["walk"] = (float(argv[i + 1]), float(argv[i + 2]))
            i += 2
        elif a == "--candidate" and i + 3 < len(argv):
            options["candidate"] = tuple(float(x) for x in argv[i + 1:i + 4])
            i += 3
        elif a == "--yaw-bias" and i + 4 < len(argv):
            options["yaw_bias"] = tuple(float(x) for x in argv[i + 1:i + 5])
            i += 4
        elif a.startswith("-"):
            raise SystemExit(f"sigma_terms: error: unknown or incomplete option {a} (--help)")
        else:
            options["dirs"].append(a)
        i += 1
    if not options["dirs"]:
        raise SystemExit("sigma_terms: error: no folder given (--help)")
    return options


def main(argv):
    options = parse(argv)
    flights = [flight(name, path, options["walk"], options["candidate"], options["yaw_bias"])
               for name, path in flight_files(options["dirs"], "series.csv", "sigma_terms")]
    if not flights:
        raise SystemExit("sigma_terms: error: no <flight>/series.csv under " + " ".join(options["dirs"]))
    models = ["reported", "rest"] + (["candidate"] if options["candidate"] else []) + \
        (["yaw_bias"] if options["yaw_bias"] else [])
    summary = {}
    for m in models:
        finals = [f[m]["final_nees"] for f in flights]
        summary[m] = {"final_nees_mean": sum(finals) / len(finals),
                      "final_nees_within_95_pct": 100.0 * sum(v <= 5.991 for v in finals) / len(finals),
                      "mean_nees_over_poses": sum(f[m]["mean_nees"] for f in flights) / len(flights),
                      "beyond_pl_pct": 100.0 * sum(f[m]["beyond_pl"] for f in flights) / sum(f["poses"] for f in flights)}
    if options["json"]:
        print(json.dumps({"flights": flights, "summary": summary, "walk": options["walk"],
                          "candidate": options["candidate"]}, indent=1))
        return 0
    print(f"{'flight':34s} {'km':>5s} {'err n':>6s} {'err e':>6s} {'sig n':>6s} {'sig e':>6s} {'relief n':>8s} "
          f"{'relief e':>8s} {'rest n':>6s} {'rest e':>6s}  final NEES: " + " / ".join(models))
    for f in flights:
        print(f"{f['flight']:34s} {f['distance_m'] / 1000:5.1f} {f['error_n_m']:6.2f} {f['error_e_m']:6.2f} "
              f"{f['sigma_n_m']:6.2f} {f['sigma_e_m']:6.2f} {f['relief_sigma_n_m']:8.2f} {f['relief_sigma_e_m']:8.2f} "
              f"{f['rest_sigma_n_m']:6.2f} {f['rest_sigma_e_m']:6.2f}  "
              + " / ".join(f"{f[m]['final_nees']:.2f}" for m in models))
    kind = "2-D" if all(f["nees_2d"] for f in flights) else "per-axis (no cov_ne_m2 in some series.csv)"
    print(f"{len(flights)} flights, horizontal NEES {kind}:")
    for m in models:
        s = summary[m]
        print(f"  {m:9s} final-pose mean {s['final_nees_mean']:.2f} ({s['final_nees_within_95_pct']:.0f} % within 5.991), "
              f"average over poses {s['mean_nees_over_poses']:.2f}, beyond the protection level {s['beyond_pl_pct']:.2f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
