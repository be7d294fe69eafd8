#!/usr/bin/python3
"""The table of studies/map_fixes/heading_bias.sh: one row per flight folder under logs/heading_bias/
(or the folders given), final and 95th-percentile horizontal error and horizontal NEES of each run."""
import argparse
import json
import pathlib

RUNS = [("no_map", "no map"), ("all_fixes_estimate_false", "all fixes, bias held"),
        ("all_fixes_estimate_true", "all fixes, bias estimated"), ("half_fixes_estimate_false", "half, held"),
        ("half_fixes_estimate_true", "half, estimated")]


def main():
    root = pathlib.Path(__file__).resolve().parents[2]
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("folders", nargs="*", help="flight folders (default: every one under logs/heading_bias/)")
    args = parser.parse_args()
    folders = [pathlib.Path(f) for f in args.folders] or sorted((root / "logs" / "heading_bias").glob("*-*-*"))
    print("| flight | " + " | ".join(name for _, name in RUNS) + " |")
    print("|---" * (len(RUNS) + 1) + "|")
    for folder in folders:
        cells = []
        for run, _ in RUNS:
            path = folder / f"{run}.json"
            if not path.exists():
                cells.append("")
                continue
            m = json.loads(path.read_text())
            cells.append(f"{m['final_error_h_m']:.2f} / {m['p95_error_h_m']:.2f} m, {m['nees_h_mean']:.2f}"
                         f" ({m['pl_exceeded_pct']:.1f} %)")
        set_name, profile_seed = folder.name.split("-", 1)
        profile, seed = profile_seed.rsplit("-", 1)
        print(f"| `{profile}` {seed}, `{set_name}` | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
