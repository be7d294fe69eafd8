#!/usr/bin/python3
"""A crossing of featureless ground flown with map fixes: what the fixes and the
estimate did over it and after it.

Reads an evaluation's series.csv (nadir_eval --out DIR) and the box the
profile cuts (terrain.featureless: north_m, east_m). Inside is the aircraft's
true position within the box. Prints, as JSON: fixes applied before, inside
and after the box; the horizontal error and sigma at entry, at most inside
and at exit; how long after the exit the first fix came and the error was
back within its bound (the 95th percentile of the error before the entry,
at least 2 m).

Usage: crossing_recovery.py REPORT_DIR NORTH_MIN NORTH_MAX EAST_MIN EAST_MAX
"""
import csv
import json
import sys

FLAG_MAP_FIX_APPLIED = 32


def main(argv):
    if len(argv) != 6:
        sys.exit(__doc__)
    report, box = argv[1], [float(v) for v in argv[2:6]]
    with open(f"{report}/series.csv") as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    if not rows:
        sys.exit(f"{report}/series.csv: no rows")

    def inside(r):
        return box[0] <= r["true_n"] <= box[1] and box[2] <= r["true_e"] <= box[3]

    first = next((i for i, r in enumerate(rows) if inside(r)), None)
    if first is None:
        sys.exit("the flight never enters the box")
    last = max(i for i, r in enumerate(rows) if inside(r))
    fix = [int(r["flags"]) & FLAG_MAP_FIX_APPLIED != 0 for r in rows]
    before = sorted(r["error_h_m"] for r in rows[:first])
    bound = max(2.0, before[int(0.95 * (len(before) - 1))]) if before else 2.0
    exit_t = rows[last]["t_s"]
    first_fix_after = next((r["t_s"] - exit_t for i, r in enumerate(rows) if i > last and fix[i]), None)
    back = next((r["t_s"] - exit_t for r in rows[last + 1:] if r["error_h_m"] <= bound), None)
    crossing = rows[first:last + 1]
    worst = max(crossing, key=lambda r: r["error_h_m"])
    out = {
        "entry_s": rows[first]["t_s"], "exit_s": exit_t,
        "fixes_before": sum(fix[:first]), "fixes_inside": sum(fix[first:last + 1]), "fixes_after": sum(fix[last + 1:]),
        "error_at_entry_m": rows[first]["error_h_m"], "sigma_at_entry_m": rows[first]["sigma_h_m"],
        "max_error_inside_m": worst["error_h_m"], "max_error_inside_at_s": worst["t_s"],
        "error_at_exit_m": rows[last]["error_h_m"], "sigma_at_exit_m": rows[last]["sigma_h_m"],
        "sigma_n_at_exit_m": rows[last]["sigma_n_m"], "sigma_e_at_exit_m": rows[last]["sigma_e_m"],
        "bound_m": bound, "first_fix_after_exit_s": first_fix_after, "error_within_bound_after_exit_s": back,
        "max_error_after_exit_m": max(r["error_h_m"] for r in rows[last + 1:]) if last + 1 < len(rows) else None,
    }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main(sys.argv)
