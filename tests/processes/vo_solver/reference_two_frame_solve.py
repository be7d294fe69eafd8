#!/usr/bin/python3
"""Independent reference solve of one frame pair, for the vo_solver tests.

The maximum-likelihood two-frame solve on a plane: every feature is a point on
the ground plane (two unknowns per point, its coordinates in the plane), seen
in both images; the unknowns are the camera translation prev -> curr in the
level frame of prev (dx, dy, dz), the heading change dyaw, the plane's roll and
pitch (the plane passes through the curr altimeter spot), and the 2 m point
coordinates. Levenberg-Marquardt on the reprojection errors in both images
(pixels). Written from the conventions in DERIVATION.md section 1 only; it
shares no code with the solver (numpy, no nadir code).

Input (text, whitespace separated): a line `pairs N`, then per pair
    prev_roll prev_pitch prev_yaw curr_roll curr_pitch curr_yaw   (INS, rad)
    curr_range_m beam_x beam_y beam_z                             (curr altimeter, body frame)
    r00 r01 r02 r10 r11 r12 r20 r21 r22                           (body_from_camera, row-major)
    focal_px m
    m lines: prev_x prev_y curr_x curr_y                          (undistorted normalized)
Output: one line per pair `dx dy dz dyaw ground_roll ground_pitch rms_px iterations`.

Usage: reference_two_frame_solve.py IN OUT [--help]
"""

import sys

import numpy as np


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def wrap(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


class Pair:
    def __init__(self, attitude, altimeter, body_from_camera, focal, points, where):
        self.where = where
        pr, pp, py, cr, cp, cy = attitude
        self.ins_dyaw = wrap(cy - py)
        # Level virtual camera <- camera: Ry(pitch) Rx(roll) R_body_camera.
        self.prev_level = rot_y(pp) @ rot_x(pr) @ body_from_camera
        self.curr_level = rot_y(cp) @ rot_x(cr) @ body_from_camera
        beam = rot_y(cp) @ rot_x(cr) @ np.asarray(altimeter[1:4])
        self.spot = altimeter[0] * beam / np.linalg.norm(beam)  # in the level frame of curr
        self.focal = focal
        self.prev = points[:, 0:2]
        self.curr = points[:, 2:4]


def read_pairs(path):
    tokens = []
    with open(path, encoding="ascii") as f:
        for line_number, line in enumerate(f, 1):
            tokens.extend((word, line_number) for word in line.split())
    pos = 0

    def take(count):
        nonlocal pos
        if pos + count > len(tokens):
            raise ValueError(f"{path}: ends early (after line {tokens[-1][1] if tokens else 0})")
        chunk = tokens[pos:pos + count]
        pos += count
        try:
            return [float(word) for word, _ in chunk]
        except ValueError:
            bad = next(t for t in chunk if not _is_float(t[0]))
            raise ValueError(f"{path}:{bad[1]}: '{bad[0]}' is not a number") from None

    if not tokens or tokens[0][0] != "pairs":
        raise ValueError(f"{path}:1: expected 'pairs N'")
    pos = 1
    count = int(take(1)[0])
    pairs = []
    for _ in range(count):
        where = f"{path}:{tokens[pos][1]}"
        attitude = take(6)
        altimeter = take(4)
        body_from_camera = np.array(take(9)).reshape(3, 3)
        focal, m = take(2)
        points = np.array(take(4 * int(m))).reshape(int(m), 4)
        pairs.append(Pair(attitude, altimeter, body_from_camera, focal, points, where))
    return pairs


def _is_float(word):
    try:
        float(word)
        return True
    except ValueError:
        return False


def plane_axes(ground_roll, ground_pitch):
    r = rot_y(ground_pitch) @ rot_x(ground_roll)
    return r[:, 0], r[:, 1], r[:, 2]


def project(points_camera):
    return points_camera[:, 0:2] / points_camera[:, 2:3]


def residuals(pair, g, ab):
    """g = (dx, dy, dz, dyaw, ground_roll, ground_pitch); ab = m x 2 plane coordinates."""
    e1, e2, _ = plane_axes(g[4], g[5])
    x_curr = pair.spot + ab[:, 0:1] * e1 + ab[:, 1:2] * e2  # level frame of curr
    x_prev = x_curr @ rot_z(g[3]).T + g[0:3]  # level frame of prev
    r_curr = project(x_curr @ pair.curr_level) - pair.curr  # level -> camera is the transpose
    r_prev = project(x_prev @ pair.prev_level) - pair.prev
    return pair.focal * np.hstack([r_prev, r_curr])  # m x 4


def initial_guess(pair):
    """INS heading change, level plane, points where the curr rays meet it, mean level flow."""
    rays_curr = pair.curr_level @ np.vstack([pair.curr.T, np.ones(len(pair.curr))])
    rays_prev = pair.prev_level @ np.vstack([pair.prev.T, np.ones(len(pair.prev))])
    height = pair.spot[2]
    x_curr = (height * rays_curr / rays_curr[2]).T
    ab = x_curr[:, 0:2] - pair.spot[0:2]
    rotated = x_curr @ rot_z(pair.ins_dyaw).T
    on_prev = (height * rays_prev / rays_prev[2]).T
    g = np.zeros(6)
    g[0:2] = np.mean(on_prev[:, 0:2] - rotated[:, 0:2], axis=0)
    g[3] = pair.ins_dyaw
    return g, ab


def solve(pair, max_iterations=200):
    g, ab = initial_guess(pair)
    m = len(ab)
    r = residuals(pair, g, ab)
    cost = float(np.sum(r * r))
    lam = 1e-3
    iterations = 0
    for _ in range(max_iterations):
        # Jacobian: 6 global columns; the point columns are block diagonal
        # (a feature's residuals depend on its own point only), so one
        # perturbation of all points' a (then b) gives all of them.
        jg = np.zeros((m, 4, 6))
        for k in range(6):
            h = 1e-6 if k < 3 else 1e-8
            gp, gm = g.copy(), g.copy()
            gp[k] += h
            gm[k] -= h
            jg[:, :, k] = (residuals(pair, gp, ab) - residuals(pair, gm, ab)) / (2 * h)
        jp = np.zeros((m, 4, 2))
        for k in range(2):
            h = 1e-6
            ap, am = ab.copy(), ab.copy()
            ap[:, k] += h
            am[:, k] -= h
            jp[:, :, k] = (residuals(pair, g, ap) - residuals(pair, g, am)) / (2 * h)
        n = 6 + 2 * m
        jac = np.zeros((4 * m, n))
        for i in range(m):
            jac[4 * i:4 * i + 4, 0:6] = jg[i]
            jac[4 * i:4 * i + 4, 6 + 2 * i:8 + 2 * i] = jp[i]
        rv = r.reshape(-1)
        a = jac.T @ jac
        b = -jac.T @ rv
        improved = False
        while lam < 1e12:
            damped = a + lam * np.diag(np.diag(a))
            try:
                step = np.linalg.solve(damped, b)
            except np.linalg.LinAlgError:
                lam *= 10
                continue
            g_trial = g + step[0:6]
            ab_trial = ab + step[6:].reshape(m, 2)
            r_trial = residuals(pair, g_trial, ab_trial)
            trial_cost = float(np.sum(r_trial * r_trial))
            if np.isfinite(trial_cost) and trial_cost <= cost:
                g, ab, r = g_trial, ab_trial, r_trial
                converged = cost - trial_cost <= 1e-12 * max(cost, 1e-30) or np.max(np.abs(step)) < 1e-10
                cost = trial_cost
                lam = max(lam * 0.1, 1e-12)
                improved = True
                iterations += 1
                break
            lam *= 10
        if not improved or converged:
            break
    rms = float(np.sqrt(cost / (2 * m)))
    return g, rms, iterations


def main(argv):
    if len(argv) != 3 or "--help" in argv:
        print(__doc__)
        return 0 if "--help" in argv else 2
    try:
        pairs = read_pairs(argv[1])
    except (OSError, ValueError) as e:
        print(f"reference_two_frame_solve: {e}", file=sys.stderr)
        return 1
    with open(argv[2], "w", encoding="ascii") as out:
        for pair in pairs:
            g, rms, iterations = solve(pair)
            g[3] = wrap(g[3])
            out.write(" ".join(f"{v:.12g}" for v in g) + f" {rms:.6g} {iterations}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
