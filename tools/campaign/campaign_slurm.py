"""Submitting a campaign to Slurm: one job array over the pending cells (one
task per cell, at most `concurrency` at once) and an aggregation job that
starts when the whole array ended well (--dependency=afterok). A cell that
fails is recorded (failed.json with its log) and its task still ends well, so
the aggregate of the others runs and reports it as missing."""
import json
import os
import shlex
import subprocess
import time

HERE = os.path.dirname(os.path.realpath(__file__))
TOOL = os.path.join(HERE, "nadir_campaign.py")


def _header(spec, name, out_pattern, root, extra):
    lines = ["#!/bin/bash", f"#SBATCH --job-name={name}", f"#SBATCH --output={out_pattern}",
             f"#SBATCH --chdir={root}", f"#SBATCH --time={spec.slurm['time_limit']}"]
    if spec.slurm["partition"]:
        lines.append(f"#SBATCH --partition={spec.slurm['partition']}")
    lines += [f"#SBATCH {e}" for e in extra]
    build = os.environ.get("NADIR_BUILD", os.path.join(root, "build"))
    lines += ["set -euo pipefail", f"export NADIR_BUILD={shlex.quote(os.path.abspath(build))}"]
    return lines


def write_scripts(spec, root, out, campaign_copy, pending_ids, stamp):
    """Writes the cell list and the two batch scripts under OUT/slurm; returns their paths."""
    sdir = os.path.join(out, "slurm")
    os.makedirs(sdir, exist_ok=True)
    cell_list = os.path.join(sdir, f"cells-{stamp}.txt")
    with open(cell_list, "w") as f:
        f.write("".join(c + "\n" for c in pending_ids))
    version_file = os.path.join(sdir, f"code_version-{stamp}.json")
    q = shlex.quote
    array = _header(spec, f"nadir-{spec.name}", os.path.join(sdir, "task-%A_%a.out"), root,
                    [f"--array=0-{len(pending_ids) - 1}%{spec.slurm['concurrency']}",
                     f"--cpus-per-task={spec.slurm['cpus_per_task']}"])
    array.append(f"exec /usr/bin/python3 {q(TOOL)} run-cell {q(campaign_copy)} --out {q(out)} "
                 f"--list {q(cell_list)} --index \"$SLURM_ARRAY_TASK_ID\" --version-file {q(version_file)}")
    agg = _header(spec, f"nadir-{spec.name}-aggregate", os.path.join(sdir, "aggregate-%j.out"), root, [])
    agg.append(f"exec /usr/bin/python3 {q(TOOL)} aggregate {q(campaign_copy)} --out {q(out)}")
    paths = {"cells": cell_list, "version": version_file, "array": os.path.join(sdir, f"cells-{stamp}.sbatch"),
             "aggregate": os.path.join(sdir, f"aggregate-{stamp}.sbatch")}
    for key, lines in (("array", array), ("aggregate", agg)):
        with open(paths[key], "w") as f:
            f.write("\n".join(lines) + "\n")
    return paths


def sbatch(script, *args):
    """Submits a batch script; returns the job id."""
    r = subprocess.run(["sbatch", "--parsable", *args, script], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"sbatch {script} failed: {r.stderr.strip() or r.stdout.strip()}")
    return r.stdout.strip().split(";")[0]


def record_jobs(out, entry):
    path = os.path.join(out, "slurm", "jobs.json")
    jobs = []
    if os.path.exists(path):
        with open(path) as f:
            jobs = json.load(f)
    jobs.append({**entry, "submitted_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())})
    with open(path, "w") as f:
        json.dump(jobs, f, indent=1)
    return jobs


def last_jobs(out):
    path = os.path.join(out, "slurm", "jobs.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)[-1]


def queue_states(job_ids):
    """{job id: [states of its tasks still known to Slurm]}, or None when squeue cannot be asked."""
    try:
        r = subprocess.run(["squeue", "-h", "-j", ",".join(job_ids), "-o", "%F %T", "--states=all"],
                           capture_output=True, text=True)
    except OSError:
        return None
    if r.returncode != 0:
        return None
    states = {j: [] for j in job_ids}
    for line in r.stdout.splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0] in states:
            states[parts[0]].append(parts[1])
    return states
