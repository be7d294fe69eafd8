#!/usr/bin/env python3
"""Draws the frames and sign conventions figure of the README (docs/images/conventions.png)
and prints the worked example: a gimbal camera attitude converted into the project's INS
roll/pitch/yaw and camera mount.

Usage: plot_conventions.py [--out PNG] [--example-only]
"""
import argparse
import math

import numpy as np


def rot(axis, deg):
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rpy_to_matrix(roll, pitch, yaw):
    """common/geometry.h rotation_from_rpy: R_world_body = Rz(yaw) Ry(pitch) Rx(roll), NED, degrees."""
    return rot("z", yaw) @ rot("y", pitch) @ rot("x", roll)


def matrix_to_rpy(r):
    pitch = math.degrees(math.asin(max(-1.0, min(1.0, -r[2, 0]))))
    roll = math.degrees(math.atan2(r[2, 1], r[2, 2]))
    yaw = math.degrees(math.atan2(r[1, 0], r[0, 0]))
    return roll, pitch, yaw


def worked_example():
    """A stabilised gimbal reports its own attitude (yaw 100, pitch -88, roll 1 deg; gimbal frame
    x = optical axis, y = image right, z = image down, ZYX in NED, as DJI-style gimbals do).
    The project wants INS roll/pitch/yaw of a body and a fixed camera mount."""
    r_world_gimbal = rpy_to_matrix(1.0, -88.0, 100.0)
    # Camera frame of the project: x image right, y image down, z optical axis.
    r_gimbal_camera = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0]], dtype=float)
    r_world_camera = r_world_gimbal @ r_gimbal_camera
    # Choose the mount "image top = forward": camera x = body right, camera y = body back.
    r_body_camera = rpy_to_matrix(0.0, 0.0, 90.0)
    r_world_body = r_world_camera @ r_body_camera.T
    roll, pitch, yaw = matrix_to_rpy(r_world_body)
    lines = [
        "R_world_camera = R_world_gimbal(roll 1, pitch -88, yaw 100) R_gimbal_camera",
        "R_gimbal_camera columns (camera x, y, z in gimbal axes): %s" % r_gimbal_camera.T.tolist(),
        "mount_rpy_deg [0, 0, 90]  (camera x = body right, camera y = body back, z = down)",
        "R_world_body = R_world_camera R_body_camera^T  ->  INS roll %.3f, pitch %.3f, yaw %.3f deg"
        % (roll, pitch, yaw),
        "optical axis in NED: %s" % np.round(r_world_camera[:, 2], 4).tolist(),
    ]
    return lines, (roll, pitch, yaw)


def arrow(ax, x0, y0, dx, dy, label, color, **kw):
    ax.annotate("", xy=(x0 + dx, y0 + dy), xytext=(x0, y0), arrowprops=dict(arrowstyle="->", color=color, lw=2))
    ax.text(x0 + 1.12 * dx, y0 + 1.12 * dy, label, color=color, ha="center", va="center", **kw)


def draw(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Arc, Polygon, Rectangle

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2))
    # (a) Top view, north up: world NED, body, camera, image.
    ax = axes[0]
    ax.set_title("(a) top view (looking down), nominal mount")
    arrow(ax, -2.6, -2.6, 0, 1.0, "N = x_world", "gray")
    arrow(ax, -2.6, -2.6, 1.0, 0, "   E = y_world", "gray")
    ax.text(-2.6, -2.95, "z_world = down (into the page)", color="gray", fontsize=8, ha="left")
    yaw = math.radians(30)
    fwd = np.array([math.sin(yaw), math.cos(yaw)])  # plotted as (east, north)
    right = np.array([math.cos(yaw), -math.sin(yaw)])
    body = np.array([0.3, 0.2])
    hull = [body + 1.3 * fwd, body - 0.8 * fwd + 0.5 * right, body - 0.8 * fwd - 0.5 * right]
    ax.add_patch(Polygon(hull, closed=True, fc="#dde", ec="k"))
    arrow(ax, *body, *(1.9 * fwd), "x_body = forward\n= x_camera = image u (right)", "C0", fontsize=8)
    arrow(ax, *body, *(1.6 * right), "y_body = right\n= y_camera = image v (down)", "C1", fontsize=8)
    ax.add_patch(Arc((0.3, 0.2), 2.0, 2.0, theta1=90 - 30, theta2=90, color="C3", lw=1.5))
    ax.text(-1.6, 1.9, "yaw > 0: clockwise\nfrom north", color="C3", fontsize=8)
    ax.set_xlim(-3, 3)
    ax.set_ylim(-3.1, 3)
    ax.set_aspect("equal")
    ax.axis("off")

    # (b) Side view: pitch, camera axis, ground pitch.
    ax = axes[1]
    ax.set_title("(b) side view (from the right), z down")
    ax.plot([-3, 3], [-2.0 - 3 * math.tan(math.radians(12)), -2.0 + 3 * math.tan(math.radians(12))], "g-", lw=3)
    ax.text(0.2, -2.5, "ground pitch > 0:\nground rises ahead", color="g", fontsize=8)
    p = math.radians(10)
    c = np.array([-0.8, 1.2])
    arrow(ax, *c, 1.6 * math.cos(p), 1.6 * math.sin(p), "x_body (pitch > 0:\nnose up)", "C0", fontsize=8)
    arrow(ax, *c, 1.4 * math.sin(p), -1.4 * math.cos(p), "z_body = z_camera\n(optical axis)", "C2", fontsize=8)
    arrow(ax, *c, 1.3, 0, "", "gray")
    ax.text(-2.9, 2.2, "level frame V: x forward along heading,\nz down (vertical); VO_DELTA dx, dy, dz\n"
            "is in V of the previous frame", fontsize=8)
    ax.set_xlim(-3, 3)
    ax.set_ylim(-3, 3)
    ax.set_aspect("equal")
    ax.axis("off")

    # (c) The image as stored.
    ax = axes[2]
    ax.set_title("(c) the image (nominal mount)")
    ax.add_patch(Rectangle((0, 0), 6.12, 5.12, fc="#f4f4f4", ec="k"))
    arrow(ax, 0.2, 4.92, 1.5, 0, "u (column) = x_camera\n= body forward", "C0", fontsize=8)
    arrow(ax, 0.2, 4.92, 0, -1.5, "", "C1")
    ax.text(0.35, 3.6, "v (row) = y_camera = body right", color="C1", fontsize=8)
    ax.text(3.06, 2.56, "+", fontsize=16, ha="center", va="center")
    ax.text(3.06, 2.1, "(cx, cy): optical axis", fontsize=8, ha="center")
    ax.text(0.1, -0.75, "flight direction: to the right of the image;\nground moves to the left (-u).\n"
            "dyaw > 0 (turn right): image content rotates\ncounter-clockwise on screen.", fontsize=8)
    ax.text(0.1, -1.6, "ground roll > 0: ground falls to the right (+v side)", fontsize=8, color="g")
    ax.set_xlim(-0.3, 6.6)
    ax.set_ylim(-1.9, 5.5)
    ax.set_aspect("equal")
    ax.axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/images/conventions.png", help="PNG to write")
    parser.add_argument("--example-only", action="store_true", help="print the worked example, draw nothing")
    args = parser.parse_args()
    lines, _ = worked_example()
    print("\n".join(lines))
    if not args.example_only:
        draw(args.out)
        print("wrote", args.out)


if __name__ == "__main__":
    main()
