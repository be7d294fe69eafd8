#!/usr/bin/python3
"""Over relief: the solver scales each pair with the barometric height as if it
were the height above ground, so a pair's step comes out as the true step times
(barometric height / true height above ground). Compares, per solved pair of an
evaluated replay (nadir_eval's pairs.csv), the step measured / true with that
ratio at the pair's first photo (from the simulator's GROUND_TRUTH: down and
height above ground at the frame).

Usage: step_ratio.py SIM.lcmlog PAIRS.csv
"""
import bisect
import csv
import math
import struct
import sys


def frames(path):
    """(utime, height above take-off, true height above ground) of every KIND_FRAME truth."""
    data = open(path, "rb").read()
    out = []
    pos = 0
    while pos + 28 <= len(data):
        sync, _, _, clen, dlen = struct.unpack_from(">IqqII", data, pos)
        if sync != 0xEDA1DA01:
            sys.exit(f"{path}: byte {pos}: no sync word")
        channel = data[pos + 28:pos + 28 + clen].decode()
        body = data[pos + 28 + clen:pos + 28 + clen + dlen]
        # ground_truth_t after its 8-byte fingerprint: utime, kind, position[3], velocity[3],
        # roll, pitch, yaw, height_agl_m.
        if channel == "GROUND_TRUTH" and body[16] == 1:
            utime, = struct.unpack_from(">q", body, 8)
            down, = struct.unpack_from(">d", body, 17 + 2 * 8)
            agl, = struct.unpack_from(">d", body, 17 + 9 * 8)
            out.append((utime, -down, agl))
        pos += 28 + clen + dlen
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    truth = frames(sys.argv[1])
    times = [t for t, _, _ in truth]
    rows = []
    for r in csv.DictReader(open(sys.argv[2])):
        if r["solved"] != "1":
            continue
        k = bisect.bisect_left(times, int(r["prev_utime"]))
        if k >= len(truth) or abs(times[k] - int(r["prev_utime"])) > 1000:
            continue
        _, baro, agl = truth[k]
        true_step = math.hypot(float(r["true_x"]), float(r["true_y"]))
        step = math.hypot(float(r["dx"]), float(r["dy"]))
        rows.append((step / true_step, baro / agl))
    if not rows:
        sys.exit("no solved pair matched a truth frame")
    n = len(rows)
    mx = sum(b for _, b in rows) / n
    my = sum(a for a, _ in rows) / n
    sxy = sum((b - mx) * (a - my) for a, b in rows)
    sxx = sum((b - mx) ** 2 for _, b in rows)
    syy = sum((a - my) ** 2 for a, _ in rows)
    slope = sxy / sxx if sxx > 0 else float("nan")
    corr = sxy / math.sqrt(sxx * syy) if sxx > 0 and syy > 0 else float("nan")
    resid = sorted(abs(a - b) for a, b in rows)
    print(f"{n} solved pairs: barometric / true height {min(b for _, b in rows):.3f}-{max(b for _, b in rows):.3f}; "
          f"step measured / true {min(a for a, _ in rows):.3f}-{max(a for a, _ in rows):.3f}; "
          f"fit slope {slope:.2f}, correlation {corr:.2f}; |measured - predicted ratio| median "
          f"{resid[n // 2]:.3f}, max {resid[-1]:.3f}")


if __name__ == "__main__":
    main()
