#!/usr/bin/python3
"""nadir_campaign: Monte Carlo campaigns of simulated flights.

A campaign file (config/campaigns/*.yaml) lists profiles x seeds x sensor sets
x solver variants (+ config overrides, shortened flights). One cell = simulate,
replay in lockstep, evaluate (launch_scripts/eval_common.sh), keeping only its
metrics and series. Results go under logs/campaigns/NAME (or --out).

  plan       list the cells and what is done
  run        --local -j N: run the cells not done yet on this machine (resumable)
  submit     --slurm: a job array over the pending cells + an aggregation job (afterok)
  status     done / failed / pending cells (and the Slurm jobs, if submitted)
  aggregate  table.md, aggregate.json and distribution.png under OUT/aggregate
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import campaign_cells  # noqa: E402
import campaign_slurm  # noqa: E402
import campaign_spec  # noqa: E402
import campaign_stats  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))


class UsageError(Exception):
    pass


def out_dir(args, spec):
    return os.path.abspath(args.out or os.path.join(ROOT, "logs", "campaigns", spec.name))


def states(out, spec):
    return {c["id"]: campaign_cells.state(out, c) for c in spec.cells}


def cmd_plan(args, spec, out):
    st = states(out, spec)
    print(f"campaign {spec.name}: {len(spec.cells)} cells -> {out}")
    for o in spec.cells[0]["config_overlays"] if spec.cells else []:
        print(f"  config overlay {o['file']} (sha256 {o['sha256'][:12]})")
    for c in spec.cells:
        overrides = " ".join(f"{k}={v}" for k, v in c["config_overrides"].items())
        sim = " ".join(f"{k}={v}" for k, v in c["sim"].items())
        print(f"  {st[c['id']][0]:8} {c['id']}  {sim} {overrides}".rstrip())
    return 0


def _pending(spec, out, version):
    """Cells to run: not done (failed and stale ones run again). Notes done cells of another version."""
    todo, other_versions = [], set()
    for c in spec.cells:
        kind, data = campaign_cells.state(out, c)
        if kind == "done":
            if data["code_version"]["version"] != version["version"]:
                other_versions.add(data["code_version"]["version"])
        else:
            todo.append(c)
    if other_versions:
        print(f"nadir_campaign: note: done cells kept from code version(s) {', '.join(sorted(other_versions))}; "
              f"now {version['version']} (aggregate refuses the mix unless --allow-mixed; --redo runs all again)")
    return todo


def _save_campaign(spec, out):
    os.makedirs(out, exist_ok=True)
    copy = os.path.join(out, "campaign.yaml")
    if os.path.abspath(spec.path) != copy:
        shutil.copyfile(spec.path, copy)
    return copy


def cmd_run(args, spec, out):
    if not args.local:
        raise UsageError("run needs --local (for a cluster: submit --slurm)")
    if args.jobs < 1:
        raise UsageError("-j must be at least 1")
    _save_campaign(spec, out)
    version = campaign_cells.code_version(ROOT)
    todo = spec.cells if args.redo else _pending(spec, out, version)
    print(f"campaign {spec.name}: {len(spec.cells) - len(todo)} of {len(spec.cells)} cells done, running "
          f"{len(todo)} with {args.jobs} process(es), code {version['version']} -> {out}", flush=True)
    failed = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(campaign_cells.run, ROOT, out, spec, c, version): c for c in todo}
        for n, f in enumerate(concurrent.futures.as_completed(futures), start=1):
            c = futures[f]
            ok = f.result()
            log = os.path.join(campaign_cells.cell_dir(out, c), "cell.log")
            print(f"  [{n}/{len(todo)}] {c['id']}: {'done' if ok else 'FAILED, log ' + log}", flush=True)
            if not ok:
                failed.append(c["id"])
    if failed:
        print(f"nadir_campaign: {len(failed)} cell(s) failed; the aggregate reports them as missing", file=sys.stderr)
        return 1
    return 0


def cmd_run_cell(args, spec, out):
    """One Slurm array task: the cell at --index of --list."""
    with open(args.list) as f:
        ids = [line.strip() for line in f if line.strip()]
    if not 0 <= args.index < len(ids):
        raise UsageError(f"--index {args.index} is outside {args.list} ({len(ids)} cells)")
    with open(args.version_file) as f:
        version = json.load(f)
    cell = spec.cell(ids[args.index])
    ok = campaign_cells.run(ROOT, out, spec, cell, version)
    log = os.path.join(campaign_cells.cell_dir(out, cell), "cell.log")
    print(f"{cell['id']}: {'done' if ok else 'FAILED, log ' + log}")
    return 0   # recorded either way: the aggregation job (afterok) must still run


def cmd_submit(args, spec, out):
    if not args.slurm:
        raise UsageError("submit needs --slurm")
    if shutil.which("sbatch") is None:
        raise UsageError("sbatch not found: no Slurm client here (a local test cluster: launch_scripts/slurm_local.sh)")
    if args.concurrency is not None:
        if args.concurrency < 1:
            raise UsageError("--concurrency must be at least 1")
        spec.slurm["concurrency"] = args.concurrency
    copy = _save_campaign(spec, out)
    version = campaign_cells.code_version(ROOT)
    todo = spec.cells if args.redo else _pending(spec, out, version)
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    paths = campaign_slurm.write_scripts(spec, ROOT, out, copy, [c["id"] for c in todo], stamp)
    with open(paths["version"], "w") as f:
        json.dump(version, f)
    entry = {"array_job": None, "aggregate_job": None, "cells": len(todo), "code_version": version["version"]}
    if todo:
        entry["array_job"] = campaign_slurm.sbatch(paths["array"])
        entry["aggregate_job"] = campaign_slurm.sbatch(paths["aggregate"], f"--dependency=afterok:{entry['array_job']}",
                                                       "--kill-on-invalid-dep=yes")
    else:
        entry["aggregate_job"] = campaign_slurm.sbatch(paths["aggregate"])
    campaign_slurm.record_jobs(out, entry)
    print(f"campaign {spec.name}: {len(todo)} cell(s) as array job {entry['array_job']} "
          f"(at most {spec.slurm['concurrency']} at once), aggregation job {entry['aggregate_job']}; "
          f"scripts in {os.path.dirname(paths['array'])}")
    print(f"submitted {entry['array_job'] or '-'} {entry['aggregate_job']}")
    return 0


def cmd_status(args, spec, out):
    st = states(out, spec)
    counts = {}
    for kind, _ in st.values():
        counts[kind] = counts.get(kind, 0) + 1
    print(f"campaign {spec.name} ({out}): " + ", ".join(f"{counts.get(k, 0)} {k}"
                                                       for k in ("done", "failed", "stale", "pending")))
    for cid, (kind, data) in st.items():
        if kind == "failed":
            print(f"  failed {cid}: exit {data.get('exit_code')}, log {data['log']}")
    jobs = campaign_slurm.last_jobs(out)
    if jobs:
        ids = [j for j in (jobs["array_job"], jobs["aggregate_job"]) if j]
        q = campaign_slurm.queue_states(ids)
        for j in ids:
            shown = "unknown to squeue" if q is None else (", ".join(sorted(set(q[j]))) or "finished")
            print(f"  slurm job {j}: {shown}")
        if args.wait:   # finished jobs stay listed (COMPLETED, FAILED...) for MinJobAge: only these are waited for
            active = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED", "RESIZING"}
            return 3 if q and any(active.intersection(q[j]) for j in ids) else 0
    agg = os.path.join(out, "aggregate", "aggregate.json")
    if os.path.exists(agg):
        print(f"  aggregate: {agg}")
    return 0


def cmd_aggregate(args, spec, out):
    results, problems = {}, {}
    for c in spec.cells:
        kind, data = campaign_cells.state(out, c)
        if kind == "done":
            results[c["id"]] = data
        else:
            problems[c["id"]] = (kind, data["log"] if data else None)
    versions = {}
    for r in results.values():
        versions.setdefault(r["code_version"]["version"], []).append(r["cell"])
    if len(versions) > 1 and not args.allow_mixed:
        detail = "; ".join(f"{v}: {len(c)} cell(s), e.g. {c[0]}" for v, c in sorted(versions.items()))
        print(f"nadir_campaign: error: results from {len(versions)} code versions ({detail}); "
              "run the old cells again (run --redo) or pass --allow-mixed", file=sys.stderr)
        return 1
    if not results:
        print(f"nadir_campaign: error: no finished cell under {out}", file=sys.stderr)
        return 1
    agg = campaign_stats.aggregate(spec, results, problems)
    agg["code_versions"] = {v: len(c) for v, c in sorted(versions.items())}
    adir = os.path.join(out, "aggregate")
    os.makedirs(adir, exist_ok=True)
    with open(os.path.join(adir, "aggregate.json"), "w") as f:
        json.dump(agg, f, indent=1, sort_keys=True)
        f.write("\n")
    text = campaign_stats.table(agg)
    with open(os.path.join(adir, "table.md"), "w") as f:
        f.write(text)
    print(text, end="")
    for m in agg["missing"]:
        print(f"missing {m['cell']} ({m['state']}){', log ' + m['log'] if m['log'] else ''}")
    print(f"code version: {', '.join(agg['code_versions'])}")
    if not args.no_plot:
        import campaign_plot   # matplotlib only when a plot is drawn
        png = os.path.join(adir, "distribution.png")
        campaign_plot.plot(agg, png, args.title or f"campaign {spec.name}: {len(results)} flights")
        print(f"plot: {png}")
    print(f"json: {os.path.join(adir, 'aggregate.json')}")
    return 0


def parser():
    p = argparse.ArgumentParser(prog="nadir_campaign", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def add(name, help_text):
        s = sub.add_parser(name, help=help_text, description=help_text)
        s.add_argument("campaign", help="campaign YAML file (config/campaigns/*.yaml)")
        s.add_argument("--out", help="results folder (default: logs/campaigns/NAME)")
        return s
    add("plan", "list the cells and their state")
    s = add("run", "run the cells not done yet on this machine (resumable)")
    s.add_argument("--local", action="store_true", help="on this machine (required)")
    s.add_argument("-j", "--jobs", type=int, default=1, help="cells run at once (default 1)")
    s.add_argument("--redo", action="store_true", help="run every cell again, done or not")
    s = add("submit", "submit the cells not done yet as a Slurm job array, then an aggregation job")
    s.add_argument("--slurm", action="store_true", help="to Slurm (required)")
    s.add_argument("--concurrency", type=int, help="array tasks at once (default: the file's slurm.concurrency)")
    s.add_argument("--redo", action="store_true", help="submit every cell again, done or not")
    s = add("status", "done / failed / pending cells, and the last Slurm submission's jobs")
    s.add_argument("--wait", action="store_true", help="exit 3 while the last submission's jobs are still queued")
    s = add("aggregate", "table, statistics, plot and JSON over the finished cells")
    s.add_argument("--allow-mixed", action="store_true", help="aggregate results of different code versions")
    s.add_argument("--no-plot", action="store_true", help="no PNG")
    s.add_argument("--title", help="plot title")
    s = sub.add_parser("run-cell", help="(used by the Slurm array) run the cell at --index of --list")
    s.add_argument("campaign")
    s.add_argument("--out", required=True)
    s.add_argument("--list", required=True)
    s.add_argument("--index", type=int, required=True)
    s.add_argument("--version-file", required=True)
    return p


COMMANDS = {"plan": cmd_plan, "run": cmd_run, "submit": cmd_submit, "status": cmd_status,
            "aggregate": cmd_aggregate, "run-cell": cmd_run_cell}


def main(argv):
    args = parser().parse_args(argv)
    try:
        spec = campaign_spec.load(args.campaign, ROOT)
        return COMMANDS[args.command](args, spec, out_dir(args, spec))
    except (campaign_spec.CampaignError, UsageError, RuntimeError) as e:
        print(f"nadir_campaign: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
