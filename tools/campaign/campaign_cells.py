"""One cell on disk: running it (run_cell.sh), its result.json (parameters,
code version, metrics) or failed.json (with its log), and its state."""
import hashlib
import json
import os
import subprocess
import time

import campaign_spec

HERE = os.path.dirname(os.path.realpath(__file__))


def code_version(root):
    """git describe, commit and dirty flag of the checkout; a dirty tree adds a hash of its diff,
    so two different uncommitted states never pass for the same version."""
    def git(*args):
        return subprocess.run(["git", "-C", root, *args], check=True, capture_output=True, text=True).stdout
    try:
        commit = git("rev-parse", "HEAD").strip()
        describe = git("describe", "--always", "--tags").strip()
        diff = git("diff", "HEAD", "--binary")
    except (OSError, subprocess.CalledProcessError):
        return {"describe": "unknown", "commit": "unknown", "dirty": True, "version": "unknown"}
    dirty = bool(diff)
    version = describe + ("-dirty-" + hashlib.sha1(diff.encode()).hexdigest()[:10] if dirty else "")
    return {"describe": describe, "commit": commit, "dirty": dirty, "version": version}


def cell_dir(out, cell):
    return os.path.join(out, "cells", cell["id"])


def params(cell):
    """What a cell's result depends on, besides the code version (overlays only when there are
    any, so that results from before overlays existed stay valid)."""
    keys = ("profile", "seed", "sensor_set", "variant", "sim", "config_overrides")
    return {k: cell[k] for k in keys + (("config_overlays",) if cell["config_overlays"] else ())}


def _write_json(path, data):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, path)   # a reader never sees half a result


def state(out, cell):
    """('done', result) | ('failed', failure) | ('stale', result) | ('pending', None).
    stale: a result for other parameters (the campaign file changed since)."""
    d = cell_dir(out, cell)
    for name, kind in (("result.json", "done"), ("failed.json", "failed")):
        path = os.path.join(d, name)
        if os.path.exists(path):
            with open(path) as f:
                data = json.load(f)
            if data.get("params") != params(cell):
                return "stale", data
            return kind, data
    return "pending", None


def run(root, out, spec, cell, version):
    """Runs one cell; writes result.json or failed.json. Returns True when it succeeded."""
    d = cell_dir(out, cell)
    os.makedirs(d, exist_ok=True)
    for name in ("result.json", "failed.json"):
        if os.path.exists(os.path.join(d, name)):
            os.remove(os.path.join(d, name))
    log_path = os.path.join(d, "cell.log")
    cmd = ["bash", os.path.join(HERE, "run_cell.sh"), cell["profile"], str(cell["seed"]), d,
           *campaign_spec.sim_args(cell), "--", *campaign_spec.replay_args(cell)]
    env = dict(os.environ, KEEP_LOGS="1" if spec.keep_logs else "0")
    start = time.time()
    with open(log_path, "w") as log:
        log.write("$ " + " ".join(cmd) + "\n")
        log.flush()
        rc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=root).returncode
    record = {"cell": cell["id"], "params": params(cell), "code_version": version, "log": log_path,
              "wall_seconds": round(time.time() - start, 3), "host": os.uname().nodename}
    metrics_path = os.path.join(d, "eval", "metrics.json")
    if rc == 0 and os.path.exists(metrics_path):
        with open(metrics_path) as f:
            record["metrics"] = json.load(f)
        _write_json(os.path.join(d, "result.json"), record)
        return True
    record["exit_code"] = rc
    _write_json(os.path.join(d, "failed.json"), record)
    return False
