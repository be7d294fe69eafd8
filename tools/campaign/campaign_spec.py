"""A campaign file: loaded, checked against the checkout (profiles, sensor sets,
config keys, config overlays) and expanded into cells. Every error names the file
and the key, and is raised before anything runs."""
import difflib
import hashlib
import itertools
import os
import re

import yaml

NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
TOP_KEYS = {"name", "description", "profiles", "seeds", "sensor_sets", "variants", "config_overlays",
            "config_overrides", "sim", "evaluate", "keep_logs", "slurm"}
# nadir_sim options a campaign may set, and the command-line flag each becomes.
SIM_KEYS = {"duration_s": "--duration", "roll_pitch_noise_deg": "--roll-pitch-noise-deg",
            "yaw_noise_deg": "--yaw-noise-deg", "altimeter_noise_pct": "--altimeter-noise-pct"}
METRIC_KEYS = ("error_pct_3d", "rms_error_pct_3d", "error_pct_h", "error_pct_v", "final_error_3d_m",
               "rms_error_3d_m", "rms_yaw_error_deg", "nees_h_mean", "nees_h_within_95_pct", "nees_yaw_mean",
               "nees_yaw_within_95_pct", "pl_exceeded_pct")
EVALUATE_DEFAULTS = {"metrics": ["error_pct_3d", "rms_error_pct_3d"], "divergence_error_pct": 5.0,
                     "bootstrap_samples": 2000, "bootstrap_seed": 1, "confidence": 0.95}
SLURM_DEFAULTS = {"concurrency": 4, "cpus_per_task": 1, "time_limit": "01:00:00", "partition": None}


class CampaignError(Exception):
    """A campaign file that cannot be run, with the file and key in the message."""


class Spec:
    """A checked campaign: its settings and its cells in a fixed order."""

    def __init__(self, path, data, cells):
        self.path = path
        self.name = data["name"]
        self.description = data.get("description", "")
        self.evaluate = data["evaluate"]
        self.slurm = data["slurm"]
        self.keep_logs = data["keep_logs"]
        self.cells = cells

    def cell(self, cell_id):
        for c in self.cells:
            if c["id"] == cell_id:
                return c
        raise CampaignError(f"{self.path}: no cell '{cell_id}' in this campaign")


def _fail(path, key, message):
    raise CampaignError(f"{path}: key '{key}': {message}")


def _unknown(path, key, name, known, what="unknown key"):
    """A key that nothing reads: the error names the nearest known one."""
    near = difflib.get_close_matches(name, sorted(known), n=1, cutoff=0.75)
    hint = f"; did you mean {key[:len(key) - len(name)]}{near[0]}?" if near else ""
    _fail(path, key, f"{what}{hint} (known: {', '.join(sorted(known))})" if len(known) < 20 else f"{what}{hint}")


def _names(path, key, value, known, what):
    if not isinstance(value, list) or not value:
        _fail(path, key, f"a non-empty list of {what} names is needed")
    for i, v in enumerate(value):
        if not isinstance(v, str) or v not in known:
            _fail(path, f"{key}[{i}]", f"unknown {what} '{v}' (known: {', '.join(sorted(known))})")
    if len(set(value)) != len(value):
        _fail(path, key, "a name is listed twice")
    return value


def _seeds(path, value):
    if isinstance(value, dict):
        unknown = set(value) - {"first", "count"}
        if unknown:
            name = sorted(unknown)[0]
            _unknown(path, f"seeds.{name}", name, {"first", "count"})
        first, count = value.get("first"), value.get("count")
        if not isinstance(first, int) or not isinstance(count, int) or first < 0 or count < 1:
            _fail(path, "seeds", "first (>= 0) and count (>= 1) must be integers")
        return list(range(first, first + count))
    if not isinstance(value, list) or not value:
        _fail(path, "seeds", "the seed list is empty (give a list of integers, or first and count)")
    for i, s in enumerate(value):
        if isinstance(s, bool) or not isinstance(s, int) or s < 0:
            _fail(path, f"seeds[{i}]", f"'{s}' is not a non-negative integer")
    if len(set(value)) != len(value):
        _fail(path, "seeds", "a seed is listed twice")
    return value


def _overlays(path, value):
    """config_overlays: YAML fragments (a calibration.yaml, an installation) merged into every
    cell's config, paths relative to the campaign file. Each is named with its content's digest,
    so a cell flown with another version of the file is flown again."""
    if value is None:
        return []
    if not isinstance(value, list):
        _fail(path, "config_overlays", "a list of YAML files is needed")
    overlays = []
    for i, name in enumerate(value):
        key = f"config_overlays[{i}]"
        if not isinstance(name, str) or not name:
            _fail(path, key, "a file name is needed")
        file = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(path)), name))
        try:
            with open(file, "rb") as f:
                content = f.read()
        except OSError as e:
            _fail(path, key, f"cannot read {file}: {e.strerror}")
        try:
            fragment = yaml.safe_load(content)
        except yaml.YAMLError as e:
            _fail(path, key, f"{file} is not valid YAML: {e}")
        if not isinstance(fragment, dict):
            _fail(path, key, f"{file}: a map of config sections is needed")
        overlays.append({"file": file, "sha256": hashlib.sha256(content).hexdigest()})
    return overlays


def _config_keys(config):
    """Every dotted key of the default config, for checking overrides before replay does."""
    keys = set()

    def walk(prefix, node):
        for k, v in node.items():
            keys.add(prefix + k)
            if isinstance(v, dict):
                walk(prefix + k + ".", v)
    walk("", config)
    return keys


def _overrides(path, key, value, config_keys):
    if value is None:
        return {}
    if not isinstance(value, dict):
        _fail(path, key, "a map of config.key: value is needed")
    for k, v in value.items():
        if k not in config_keys:
            _unknown(path, f"{key}.{k}", k, config_keys, "unknown config key (not in config/default.yaml)")
        if isinstance(v, (dict, list)) or v is None:
            _fail(path, f"{key}.{k}", "the value must be a number, a string or a boolean")
    return {k: value[k] for k in sorted(value)}


def _section(path, key, value, defaults):
    value = {} if value is None else value
    if not isinstance(value, dict):
        _fail(path, key, "a map is needed")
    for k in value:
        if k not in defaults:
            _unknown(path, f"{key}.{k}", k, defaults)
    return {**defaults, **value}


def _check_evaluate(path, ev):
    if not isinstance(ev["metrics"], list) or not ev["metrics"]:
        _fail(path, "evaluate.metrics", "a non-empty list is needed")
    for i, m in enumerate(ev["metrics"]):
        if m not in METRIC_KEYS:
            _fail(path, f"evaluate.metrics[{i}]", f"unknown metric '{m}' (known: {', '.join(METRIC_KEYS)})")
    if not isinstance(ev["divergence_error_pct"], (int, float)) or ev["divergence_error_pct"] <= 0:
        _fail(path, "evaluate.divergence_error_pct", "a positive number is needed")
    if not isinstance(ev["bootstrap_samples"], int) or ev["bootstrap_samples"] < 100:
        _fail(path, "evaluate.bootstrap_samples", "an integer >= 100 is needed")
    if not isinstance(ev["bootstrap_seed"], int):
        _fail(path, "evaluate.bootstrap_seed", "an integer is needed")
    if not isinstance(ev["confidence"], float) or not 0.5 <= ev["confidence"] < 1.0:
        _fail(path, "evaluate.confidence", "a number in [0.5, 1) is needed")


def _check_slurm(path, sl):
    for k in ("concurrency", "cpus_per_task"):
        if not isinstance(sl[k], int) or sl[k] < 1:
            _fail(path, f"slurm.{k}", "a positive integer is needed")
    if not isinstance(sl["time_limit"], str) or not re.match(r"^(\d+-)?\d+(:\d+){0,2}$", sl["time_limit"]):
        _fail(path, "slurm.time_limit", "a Slurm time such as 00:30:00 is needed")


def load(path, root):
    """Reads and checks the campaign file at path against the checkout at root."""
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise CampaignError(f"{path}: cannot read: {e.strerror}") from e
    except yaml.YAMLError as e:
        raise CampaignError(f"{path}: not valid YAML: {e}") from e
    if not isinstance(data, dict):
        raise CampaignError(f"{path}: a map of campaign keys is needed")
    for k in data:
        if k not in TOP_KEYS:
            _unknown(path, k, k, TOP_KEYS)
    for k in ("name", "profiles", "seeds"):
        if k not in data:
            _fail(path, k, "missing")
    if not isinstance(data["name"], str) or not NAME_RE.match(data["name"]):
        _fail(path, "name", "letters, digits, '_', '-' and '.' only")

    profiles_dir = os.path.join(root, "config", "profiles")
    known_profiles = {f[:-5] for f in os.listdir(profiles_dir) if f.endswith(".yaml")}
    profiles = _names(path, "profiles", data["profiles"], known_profiles, "profile")
    seeds = _seeds(path, data["seeds"])
    with open(os.path.join(root, "config", "sim_sensors.yaml")) as f:
        known_sets = set(yaml.safe_load(f))
    sensor_sets = _names(path, "sensor_sets", data.get("sensor_sets", ["standard"]), known_sets, "sensor set")
    with open(os.path.join(root, "config", "default.yaml")) as f:
        config_keys = _config_keys(yaml.safe_load(f))

    variants = data.get("variants", {"default": {}})
    if not isinstance(variants, dict) or not variants:
        _fail(path, "variants", "a non-empty map of variant name: {config.key: value} is needed")
    for name in variants:
        if not isinstance(name, str) or not NAME_RE.match(name):
            _fail(path, f"variants.{name}", "variant names take letters, digits, '_', '-' and '.' only")
    variants = {n: _overrides(path, f"variants.{n}", v, config_keys) for n, v in variants.items()}
    common = _overrides(path, "config_overrides", data.get("config_overrides"), config_keys)
    overlays = _overlays(path, data.get("config_overlays"))

    sim = _section(path, "sim", data.get("sim"), {k: None for k in SIM_KEYS})
    for k, v in sim.items():
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or v < 0):
            _fail(path, f"sim.{k}", "a non-negative number is needed")
    data["evaluate"] = _section(path, "evaluate", data.get("evaluate"), EVALUATE_DEFAULTS)
    _check_evaluate(path, data["evaluate"])
    data["slurm"] = _section(path, "slurm", data.get("slurm"), SLURM_DEFAULTS)
    _check_slurm(path, data["slurm"])
    data["keep_logs"] = data.get("keep_logs", False)
    if not isinstance(data["keep_logs"], bool):
        _fail(path, "keep_logs", "true or false")

    sim = {k: v for k, v in sim.items() if v is not None}
    cells = []
    for profile, sensor_set, variant, seed in itertools.product(profiles, sensor_sets, variants, seeds):
        cells.append({"id": f"{profile}_{sensor_set}_{variant}_seed{seed}", "profile": profile, "seed": seed,
                      "sensor_set": sensor_set, "variant": variant, "sim": dict(sim),
                      "config_overlays": overlays, "config_overrides": {**common, **variants[variant]}})
    return Spec(path, data, cells)


def sim_args(cell):
    """nadir_sim options for a cell (beyond profile and seed)."""
    args = ["--sensor-set", cell["sensor_set"]]
    for k in sorted(cell["sim"]):
        args += [SIM_KEYS[k], repr(cell["sim"][k]) if isinstance(cell["sim"][k], float) else str(cell["sim"][k])]
    return args


def replay_args(cell):
    """nadir_replay --config-overlay and --set options for a cell (overrides win)."""
    args = []
    for overlay in cell["config_overlays"]:
        args += ["--config-overlay", overlay["file"]]
    for k, v in cell["config_overrides"].items():
        args += ["--set", f"{k}={str(v).lower() if isinstance(v, bool) else v}"]
    return args
