#!/usr/bin/python3
"""The relief term's fit (docs/research/2026-12-relief-sigma.md).

Usage: relief_fit.py [--walk-paper 0.068] FLIGHT_DIR [FLIGHT_DIR ...]

Each FLIGHT_DIR is one flight of relief_sigma.sh --fit: relief0/ (nadir_eval's
pairs.csv and VO_DELTA as delta.csv, the relief term off), relief1/delta.csv
(the term at one height) and paper_walk/delta.csv (the one-plane walk raised:
the pairs the paper alone solved are those whose variance moved). Each pair's
error is split along its true step; over every window of consecutive solved
pairs of 300 m to 2 km, the mean square of the summed along error, less the
one-plane walk of the pairs the paper alone solved, is fitted by least squares
as a + walk^2 x (distance the own depths solved) + c x (the term's sum at one
height). Prints per flight the paper-alone pairs and what the windows of 1 and
2 km needed, then the pooled walk and c (heights)."""
import argparse
import csv

import numpy as np

WINDOWS_M = (300, 500, 1000, 1500, 2000)


def horizontal_variance(path):
    with open(path) as f:
        return {int(r["utime"]): float(r["var_dx"]) + float(r["var_dy"]) for r in csv.DictReader(f)}


def load(flight):
    base = horizontal_variance(f"{flight}/relief0/delta.csv")
    one = horizontal_variance(f"{flight}/relief1/delta.csv")
    raised = horizontal_variance(f"{flight}/paper_walk/delta.csv")
    step, along, relief, paper = [], [], [], []
    with open(f"{flight}/relief0/pairs.csv") as f:
        for r in csv.DictReader(f):
            t = int(r["utime"])
            if r["solved"] != "1" or t not in base or t not in one or t not in raised:
                continue
            tx, ty, dx, dy = (float(r[k]) for k in ("true_x", "true_y", "dx", "dy"))
            s = np.hypot(tx, ty)
            if s < 1e-3:
                continue
            step.append(s)
            along.append(((dx - tx) * tx + (dy - ty) * ty) / s)
            relief.append(one[t] - base[t])
            paper.append(raised[t] - base[t] > 1e-3 * s)
    return np.array(step), np.array(along), np.array(relief), np.array(paper, dtype=bool)


def windows(step, along, relief, paper, walk_paper):
    """Rows (own distance, relief sum, along^2 less the paper-alone walk) for every 5th window start."""
    cd = np.r_[0, np.cumsum(step)]
    ca = np.r_[0, np.cumsum(along)]
    cr = np.r_[0, np.cumsum(relief)]
    co = np.r_[0, np.cumsum(np.where(paper, 0.0, step))]
    cp = np.r_[0, np.cumsum(np.where(paper, step, 0.0))]
    rows = []
    for d in WINDOWS_M:
        end = np.searchsorted(cd, cd + d)
        i = np.nonzero(end < len(cd))[0][::5]
        j = end[i]
        rows += list(zip(co[j] - co[i], cr[j] - cr[i], (ca[j] - ca[i]) ** 2 - walk_paper**2 * (cp[j] - cp[i])))
    return np.array(rows).reshape(-1, 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--walk-paper", type=float, default=0.068, help="the one-plane walk (m/sqrt(m))")
    ap.add_argument("flights", nargs="+")
    a = ap.parse_args()
    pooled = []
    for flight in a.flights:
        step, along, relief, paper = load(flight)
        w = windows(step, along, relief, paper, a.walk_paper)
        if not len(w):
            print(f"{flight}: shorter than {WINDOWS_M[0]} m, left out")
            continue
        pooled.append(w)
        print(f"{flight}: {paper.sum()} of {len(paper)} pairs by the paper alone (along {along[paper].sum():+.3f} m,"
              f" the rest {along[~paper].sum():+.3f} m); term at one height {relief.sum() / step.sum():.2e} m^2/m")
        for d in (1000, 2000):
            near = np.abs(w[:, 0] - d) < 0.1 * d
            if near.any() and w[near, 1].mean() > 0:
                need = (w[near, 2].mean() - 0.006**2 * w[near, 0].mean()) / w[near, 1].mean()
                print(f"   {d} m: rms {np.sqrt(max(w[near, 2].mean(), 0)):.3f} m, c needed {need:.3f}")
    w = np.vstack(pooled)
    x = np.c_[np.ones(len(w)), w[:, 0], w[:, 1]]
    coef, *_ = np.linalg.lstsq(x, w[:, 2], rcond=None)
    print(f"pooled ({len(pooled)} flights): walk {np.sqrt(max(coef[1], 0)):.4f} m/sqrt(m), c {coef[2]:.3f} heights")
    x = np.c_[np.ones(len(w)), w[:, 1]]
    coef, *_ = np.linalg.lstsq(x, w[:, 2] - 0.006**2 * w[:, 0], rcond=None)
    print(f"walk held at 0.006: c {coef[1]:.3f} heights")


if __name__ == "__main__":
    main()
