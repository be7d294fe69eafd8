#!/usr/bin/python3
"""Seneca (real flight): nadir's VO_DELTA against independent two-frame solves.

For every frame pair of a replay (own_flight.sh run folder) it reads, with
`nadir_log dump`, the TRACKS nadir's tracker produced, the imported INS
attitude, the altimeter (height), the GPS truth (GROUND_TRUTH) and nadir's
VO_DELTA, and solves each pair again, independently of the solver's code:

  homography  image only: RANSAC homography (numpy DLT) on the tracks, then a
              Levenberg-Marquardt fit of the plane-induced homography
              H = R + (t/d) n^T with free rotation R, translation t/d and plane
              normal n (prev camera frame); the camera tilt comes from n, the
              scale from the height, only the heading from the INS/mount.
  ref_ins     the numpy maximum-likelihood plane solve of
              tests/processes/vo_solver/reference_two_frame_solve.py with the
              INS roll/pitch/heading, on the homography's inliers.
  ref_img     the same solve with the roll/pitch the homography implies for
              both frames instead of the INS roll/pitch.

Each solve's horizontal step is compared with the GPS step in the previous
frame's level frame (as nadir_eval's pairs.csv). The implied focal length of a
pair is f * |solved step| / |GPS step| (the solved step scales with 1/f).
Writes PREFIX.csv (one row per pair) and prints the summary table.

Usage: seneca_reference.py RUN_DIR [--nadir-log PATH] [--focal F] [--ins-offset-deg ROLL PITCH] [--out PREFIX]
"""

import argparse
import csv
import io
import math
import os
import subprocess
import sys

import numpy as np
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "processes", "vo_solver"))
import reference_two_frame_solve as ref  # noqa: E402  (independent numpy solve)

SOLVED_MASK = 1 | 2 | 8 | 16  # VO_DELTA quality bits that make a pair unsolved (kUnsolvedQualityMask, tools/eval)


def dump(nadir_log, log, channel):
    try:
        proc = subprocess.run([nadir_log, "dump", log, channel], capture_output=True, text=True, check=False)
    except OSError as e:
        raise RuntimeError(f"{nadir_log}: {e.strerror} (build it: cmake --build build --target nadir_log)") from None
    if proc.returncode != 0:
        raise RuntimeError(f"nadir_log dump {log} {channel}: {proc.stderr.strip()}")
    return list(csv.DictReader(io.StringIO(proc.stdout)))


def nearest(rows, utime):
    best = min(rows, key=lambda r: abs(int(r["utime"]) - utime))
    return best, abs(int(best["utime"]) - utime)


def rpy_matrix(roll, pitch, yaw):
    return ref.rot_z(yaw) @ ref.rot_y(pitch) @ ref.rot_x(roll)


def rotvec_matrix(v):
    a = np.linalg.norm(v)
    if a < 1e-15:
        return np.eye(3)
    k = v / a
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(a) * kx + (1 - math.cos(a)) * kx @ kx


def dlt(p, q):
    rows = []
    for (x, y), (u, v) in zip(p, q):
        rows.append([x, y, 1, 0, 0, 0, -u * x, -u * y, -u])
        rows.append([0, 0, 0, x, y, 1, -v * x, -v * y, -v])
    _, _, vt = np.linalg.svd(np.asarray(rows))
    h = vt[-1].reshape(3, 3)
    return h / h[2, 2] if abs(h[2, 2]) > 1e-12 else h


def transfer(h, p):
    ph = np.hstack([p, np.ones((len(p), 1))]) @ h.T
    return ph[:, 0:2] / ph[:, 2:3]


def ransac_homography(p, q, focal, threshold_px=3.0, iterations=600, seed=1):
    rng = np.random.default_rng(seed)
    best = np.zeros(len(p), bool)
    for _ in range(iterations):
        idx = rng.choice(len(p), 4, replace=False)
        try:
            h = dlt(p[idx], q[idx])
        except np.linalg.LinAlgError:
            continue
        err = focal * np.linalg.norm(transfer(h, p) - q, axis=1)
        inl = err < threshold_px
        if inl.sum() > best.sum():
            best = inl
    if best.sum() < 8:
        return None, best
    h = dlt(p[best], q[best])
    inl = focal * np.linalg.norm(transfer(h, p) - q, axis=1) < threshold_px
    return dlt(p[inl], q[inl]), inl


def plane_normal(a, b):
    return ref.rot_y(b) @ ref.rot_x(a) @ np.array([0.0, 0.0, 1.0])


def plane_homography(x):
    """x = rotvec(3), t/d (3), normal angles (2): H = R + (t/d) n^T, X_curr = R X_prev + t."""
    return rotvec_matrix(x[0:3]) + np.outer(x[3:6], plane_normal(x[6], x[7]))


def fit_plane_homography(p, q, h0, focal):
    """LM on the transfer error in the curr image, started from the DLT homography's in-plane rotation."""
    psi = math.atan2(h0[1, 0] - h0[0, 1], h0[0, 0] + h0[1, 1])
    x = np.zeros(8)
    x[2] = psi
    x[3:5] = [h0[0, 2], h0[1, 2]]

    def res(x):
        return (focal * (transfer(plane_homography(x), p) - q)).reshape(-1)

    r = res(x)
    cost = r @ r
    lam = 1e-3
    for _ in range(200):
        jac = np.zeros((len(r), 8))
        for k in range(8):
            d = np.zeros(8)
            d[k] = 1e-7
            jac[:, k] = (res(x + d) - res(x - d)) / 2e-7
        a = jac.T @ jac
        g = -jac.T @ r
        while lam < 1e12:
            step = np.linalg.solve(a + lam * np.diag(np.diag(a) + 1e-12), g)
            rt = res(x + step)
            if rt @ rt <= cost:
                done = cost - rt @ rt < 1e-12 * cost
                x, r, cost = x + step, rt, rt @ rt
                lam = max(lam / 10, 1e-12)
                break
            lam *= 10
        else:
            break
        if done:
            break
    return x, math.sqrt(cost / len(r))


def level_from_normal(body_from_camera, n_camera):
    """Level-from-camera rotation with the tilt from a ground normal (camera frame) and no INS roll/pitch:
    the mount alone, then the smallest rotation that makes the normal vertical."""
    v = body_from_camera @ n_camera
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(v, z)
    s = np.linalg.norm(axis)
    angle = math.atan2(s, v @ z)
    corr = rotvec_matrix(axis / s * angle) if s > 1e-12 else np.eye(3)
    return corr @ body_from_camera


def roll_pitch(level_from_body):
    return math.atan2(level_from_body[2, 1], level_from_body[2, 2]), -math.asin(level_from_body[2, 0])


def median(values):
    v = [x for x in values if x is not None and math.isfinite(x)]
    return float(np.median(v)) if v else float("nan")


def robust_sigma_of_median(values):
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)])
    if len(v) < 2:
        return float("nan")
    return 1.4826 * float(np.median(np.abs(v - np.median(v)))) * 1.2533 / math.sqrt(len(v))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run_dir", help="own_flight.sh run folder (replay.lcmlog, flight.yaml)")
    ap.add_argument("--nadir-log", default=os.path.join(ROOT, "build", "bin", "nadir_log"))
    ap.add_argument("--focal", type=float, default=None, help="solve with this focal length (px) instead of the camera's")
    ap.add_argument("--ins-offset-deg", type=float, nargs=2, default=[0.0, 0.0], metavar=("ROLL", "PITCH"),
                    help="added to the INS roll/pitch for ref_ins (e.g. the median image tilt - INS: a mounting offset)")
    ap.add_argument("--out", default=None, help="output prefix (default RUN_DIR/report/reference)")
    args = ap.parse_args(argv[1:])
    try:
        return run(args)
    except (OSError, RuntimeError, KeyError) as e:
        print(f"seneca_reference: error: {e}", file=sys.stderr)
        return 1


def run(args):
    log = os.path.join(args.run_dir, "replay.lcmlog")
    with open(os.path.join(args.run_dir, "flight.yaml"), encoding="utf-8") as f:
        cam = yaml.safe_load(f)["camera"]
    if any(abs(k) > 0 for k in cam.get("distortion", [0])):
        print("seneca_reference: warning: the camera has distortion; the tracks' normalized coordinates are used")
    f_cam = float(cam["fx"])
    focal = args.focal or f_cam
    scale = f_cam / focal  # normalized coordinates scale with 1/focal
    mount = [math.radians(a) for a in cam.get("mount_rpy_deg", [0, 0, 0])]
    body_from_camera = rpy_matrix(*mount)
    tracks = dump(args.nadir_log, log, "TRACKS")
    ins = dump(args.nadir_log, log, "INS")
    alt = dump(args.nadir_log, log, "ALTIMETER")
    truth = dump(args.nadir_log, log, "GROUND_TRUTH")
    deltas = {(int(d["utime"]), int(d["prev_utime"])): d for d in dump(args.nadir_log, log, "VO_DELTA")}
    by_pair = {}
    for t in tracks:
        by_pair.setdefault((int(t["utime"]), int(t["prev_utime"])), []).append(t)
    out_rows = []
    for (utime, prev_utime), d in sorted(deltas.items()):
        if prev_utime <= 0:
            continue
        rows = by_pair.get((utime, prev_utime), [])
        a, _ = nearest(truth, prev_utime)
        b, _ = nearest(truth, utime)
        ia, dta = nearest(ins, prev_utime)
        ib, dtb = nearest(ins, utime)
        al, _ = nearest(alt, utime)
        alp, _ = nearest(alt, prev_utime)
        yaw_a = float(a["yaw"])
        dn, de = float(b["north"]) - float(a["north"]), float(b["east"]) - float(a["east"])
        gps = np.array([math.cos(yaw_a) * dn + math.sin(yaw_a) * de, -math.sin(yaw_a) * dn + math.cos(yaw_a) * de])
        step = float(np.hypot(*gps))
        row = {"utime": utime, "prev_utime": prev_utime, "step_m": step, "gps_x": gps[0], "gps_y": gps[1],
               "tracks": len(rows), "ins_dt_ms": max(dta, dtb) / 1e3}

        def record(name, dx, dy):
            e = np.array([dx, dy]) - gps
            row[f"{name}_dx"], row[f"{name}_dy"] = dx, dy
            row[f"{name}_err_pct"] = 100 * float(np.hypot(*e)) / step if step > 0 else float("nan")
            row[f"{name}_len_ratio"] = float(np.hypot(dx, dy)) / step if step > 0 else float("nan")
            row[f"{name}_dir_err_deg"] = math.degrees(ref.wrap(math.atan2(dy, dx) - math.atan2(gps[1], gps[0])))

        solved = (int(d["quality"]) & SOLVED_MASK) == 0
        row["nadir_solved"] = int(solved)
        if solved:
            record("nadir", float(d["dx"]), float(d["dy"]))
        p = np.array([[float(t["prev_norm_x"]), float(t["prev_norm_y"])] for t in rows]).reshape(-1, 2) * scale
        q = np.array([[float(t["curr_norm_x"]), float(t["curr_norm_y"])] for t in rows]).reshape(-1, 2) * scale
        if len(p) < 12:
            out_rows.append(row)
            continue
        h, inl = ransac_homography(p, q, focal)
        row["h_inliers"] = int(inl.sum())
        if h is None or inl.sum() < 12:
            out_rows.append(row)
            continue
        x, rms = fit_plane_homography(p[inl], q[inl], h, focal)
        row["h_rms_px"] = rms
        r_cp = rotvec_matrix(x[0:3])
        n_prev = plane_normal(x[6], x[7])
        if n_prev[2] < 0:  # the ground is in front of the camera
            n_prev, x[3:6] = -n_prev, -x[3:6]
        level_prev = level_from_normal(body_from_camera, n_prev)
        level_curr = level_from_normal(body_from_camera, r_cp @ n_prev)
        height_prev = float(alp["range_m"])
        row["height_m"] = height_prev
        centre = -r_cp.T @ x[3:6] * height_prev  # curr camera centre in the prev camera frame, m
        hor = level_prev @ centre
        record("homography", hor[0], hor[1])
        # Camera tilt from the images against the INS (body roll/pitch the homography implies)
        ra, pa = roll_pitch(level_prev @ body_from_camera.T)
        rb, pb = roll_pitch(level_curr @ body_from_camera.T)
        row["img_roll_prev_deg"], row["img_pitch_prev_deg"] = math.degrees(ra), math.degrees(pa)
        row["ins_roll_prev_deg"], row["ins_pitch_prev_deg"] = (math.degrees(float(ia["roll"])),
                                                               math.degrees(float(ia["pitch"])))
        # The independent ML solve, with the INS roll/pitch and with the images' roll/pitch.
        pts = np.hstack([p[inl], q[inl]])
        altimeter = [float(al["range_m"]), float(al["beam_x"]), float(al["beam_y"]), float(al["beam_z"])]
        off_r, off_p = (math.radians(v) for v in args.ins_offset_deg)
        for name, att in (("ref_ins", [float(ia["roll"]) + off_r, float(ia["pitch"]) + off_p, float(ia["yaw"]),
                                       float(ib["roll"]) + off_r, float(ib["pitch"]) + off_p, float(ib["yaw"])]),
                          ("ref_img", [ra, pa, float(ia["yaw"]), rb, pb, float(ib["yaw"])])):
            pair = ref.Pair(att, altimeter, body_from_camera, focal, pts, f"{utime}")
            g, rms_ref, _ = ref.solve(pair)
            record(name, g[0], g[1])
            row[f"{name}_rms_px"] = rms_ref
        out_rows.append(row)
        print(f"pair {len(out_rows):3d}: step {step:5.1f} m  nadir {row.get('nadir_err_pct', float('nan')):6.1f} %  "
              f"homography {row['homography_err_pct']:6.1f} %  ref_ins {row['ref_ins_err_pct']:6.1f} %  "
              f"ref_img {row['ref_img_err_pct']:6.1f} %", file=sys.stderr)
    prefix = args.out or os.path.join(args.run_dir, "report", "reference")
    columns = []
    for r in out_rows:
        columns += [k for k in r if k not in columns]
    with open(prefix + ".csv", "w", newline="", encoding="ascii") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(out_rows)
    n = len(out_rows)
    print(f"{n} pairs, focal {focal:.1f} px (camera {f_cam:.1f} px), INS roll/pitch offset {args.ins_offset_deg} deg; per-pair horizontal error in % of the GPS step")
    print(f"{'solve':11s} {'solved':>7s} {'median%':>8s} {'p90%':>7s} {'len_ratio':>10s} {'|dir|deg':>9s} "
          f"{'implied_f_px':>16s} {'median%_scaled':>15s} {'median%_on_nadir_pairs':>23s}")
    for name in ("nadir", "homography", "ref_ins", "ref_img"):
        errs = [r[f"{name}_err_pct"] for r in out_rows if f"{name}_err_pct" in r]
        ratios = [r[f"{name}_len_ratio"] for r in out_rows if f"{name}_len_ratio" in r]
        dirs = [abs(r[f"{name}_dir_err_deg"]) for r in out_rows if f"{name}_dir_err_deg" in r]
        f_nadir = f_cam if name == "nadir" else focal
        implied = [f_nadir * x for x in ratios]
        p90 = float(np.percentile(errs, 90)) if errs else float("nan")
        common = [r[f"{name}_err_pct"] for r in out_rows if f"{name}_err_pct" in r and "nadir_err_pct" in r]
        # The error left when the solve's median length ratio (a focal/height scale) is divided out.
        k = median(ratios)
        scaled = [100 * math.hypot(r[f"{name}_dx"] / k - r["gps_x"], r[f"{name}_dy"] / k - r["gps_y"]) / r["step_m"]
                  for r in out_rows if f"{name}_dx" in r]
        print(f"{name:11s} {len(errs):3d}/{n:<3d} {median(errs):8.1f} {p90:7.1f} {k:10.3f} "
              f"{median(dirs):9.1f} {median(implied):9.0f} +- {robust_sigma_of_median(implied):3.0f} "
              f"{median(scaled):15.1f} {median(common):23.1f}")
    for other in ("ref_ins", "homography", "ref_img"):
        both = [r for r in out_rows if "nadir_dx" in r and f"{other}_dx" in r]
        diff = [100 * math.hypot(r["nadir_dx"] - r[f"{other}_dx"], r["nadir_dy"] - r[f"{other}_dy"]) / r["step_m"]
                for r in both]
        print(f"nadir - {other} on the {len(both)} pairs both solved: median |difference| {median(diff):.1f} % of "
              f"the step (nadir {median([r['nadir_err_pct'] for r in both]):.1f} %, {other} "
              f"{median([r[f'{other}_err_pct'] for r in both]):.1f} % against GPS)")
    # Focal or height? gps = A * s * h + B * s with s = solved length / height: A = f_solve / f_true, B = A * h0
    # (h0: an offset of the barometric height above take-off from the height above these fields).
    fit = [r for r in out_rows if "homography_dx" in r and r["homography_err_pct"] < 50]
    if len(fit) >= 5:
        s_len = np.array([math.hypot(r["homography_dx"], r["homography_dy"]) / r["height_m"] for r in fit])
        h = np.array([r["height_m"] for r in fit])
        y = np.array([r["step_m"] for r in fit])
        design = np.column_stack([s_len * h, s_len])
        coef, *_ = np.linalg.lstsq(design, y, rcond=None)
        resid = y - design @ coef
        cov = np.linalg.inv(design.T @ design) * (resid @ resid) / (len(y) - 2)
        a_sd = math.sqrt(cov[0, 0])
        print(f"homography steps (error < 50 %, {len(fit)} pairs, heights {h.min():.0f}-{h.max():.0f} m): "
              f"focal {focal / coef[0]:.0f} +- {focal * a_sd / coef[0] ** 2:.0f} px with height offset "
              f"{coef[1] / coef[0]:+.1f} +- {math.sqrt(cov[1, 1]) / coef[0]:.1f} m; focal alone (offset 0): "
              f"{focal * float(np.sum(s_len * h * s_len * h)) / float(np.sum(y * s_len * h)):.0f} px")
    dr = [r["img_roll_prev_deg"] - r["ins_roll_prev_deg"] for r in out_rows if "img_roll_prev_deg" in r]
    dp = [r["img_pitch_prev_deg"] - r["ins_pitch_prev_deg"] for r in out_rows if "img_pitch_prev_deg" in r]
    if dr:
        mad = lambda v: 1.4826 * float(np.median(np.abs(np.asarray(v) - np.median(v))))  # noqa: E731
        print(f"image tilt - INS (prev frames, {len(dr)}): roll {median(dr):+.2f} deg (robust sd {mad(dr):.2f}), "
              f"pitch {median(dp):+.2f} deg (robust sd {mad(dp):.2f})")
    print(f"rows: {prefix}.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
