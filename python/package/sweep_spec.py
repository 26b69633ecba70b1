"""A sweep's spec: one scenario (a scene, optionally a scripted device file, the seconds to run) and the
parameters to change, as a grid (every combination) or as random draws with a seed, each by its key path
in the scene or, prefixed with `script.`, in the device script:

    materials.wood.friction        mapping keys, dot-separated
    bodies[box].v                  [name]: the list entry whose `name` is box
    script.steps[0].position       [k]: the k-th list entry (from 0)

expand() turns a spec into its runs, in a fixed order, each with its parameters and its own seed, so the
same spec gives the same runs wherever and in whatever order they run."""
import copy
import hashlib
import itertools
import json
import os
import re

import numpy as np
import yaml

METRICS = ("final_pose", "final_q", "displacement", "max_penetration", "max_contacts", "max_robot_force",
           "max_user_force", "min_distance_excluding_wall", "reached_wall_time", "collision_steps",
           "contact_solve.solves", "contact_solve.unconverged", "contact_solve.max_sweeps", "contact_solve.polish_rounds",
           "contact_solve.max_residual", "diverged")
SPEC_KEYS = {"scene", "script", "seconds", "grid", "random", "metrics", "device_limits"}
_TOKEN = re.compile(r"([^.\[\]]+)|\[([^\]]*)\]")


class SpecError(ValueError):
    """A spec that cannot run, with what is wrong and where."""


def parse_key(key):
    """'bodies[box].v' -> ['bodies', ('box',), 'v']: a str is a mapping key, a 1-tuple a list selector."""
    tokens = [m.group(1) if m.group(1) is not None else (m.group(2),) for m in _TOKEN.finditer(key)]
    rebuilt = "".join(("." if i and isinstance(t, str) else "") + (t if isinstance(t, str) else f"[{t[0]}]")
                      for i, t in enumerate(tokens))
    if not tokens or isinstance(tokens[0], tuple) or rebuilt != key:
        raise SpecError(f"key '{key}': expected a path such as materials.wood.friction or bodies[box].v")
    return tokens


def _select(node, token, key):
    if isinstance(token, tuple):
        if not isinstance(node, list):
            raise SpecError(f"key '{key}': [{token[0]}] selects in a list, but here is a {type(node).__name__}")
        sel = token[0]
        if re.fullmatch(r"-?\d+", sel):
            k = int(sel)
            if not -len(node) <= k < len(node):
                raise SpecError(f"key '{key}': index {k} out of range (the list has {len(node)} entries)")
            return node, k
        names = [e.get("name") for e in node if isinstance(e, dict)]
        if sel not in names:
            raise SpecError(f"key '{key}': no entry named '{sel}' (there are: {', '.join(map(str, names))})")
        return node, names.index(sel)
    if not isinstance(node, dict):
        raise SpecError(f"key '{key}': '{token}' names a mapping key, but here is a {type(node).__name__}")
    return node, token


def set_key(doc, key, value):
    """Sets the value at key in a loaded YAML document (in place). Every part of the path but the last must exist."""
    tokens = parse_key(key)
    node = doc
    for i, token in enumerate(tokens):
        parent, k = _select(node, token, key)
        if i == len(tokens) - 1:
            parent[k] = value
            return
        if isinstance(k, str) and k not in parent:
            raise SpecError(f"key '{key}': '{k}' is not in the document (it has: {', '.join(map(str, parent))})")
        node = parent[k]


def load_spec(spec, base_dir="."):
    """A spec from a dict or a YAML file's path, checked; its scene and script paths made absolute (relative ones
    against base_dir, the current directory by default)."""
    source = "<spec>"
    if isinstance(spec, (str, os.PathLike)):
        source = str(spec)
        with open(spec) as f:
            try:
                spec = yaml.safe_load(f)
            except yaml.YAMLError as e:
                raise SpecError(f"{source}: not YAML: {e}") from None
    if not isinstance(spec, dict):
        raise SpecError(f"{source}: a sweep spec is a mapping")
    spec = copy.deepcopy(spec)
    unknown = set(spec) - SPEC_KEYS
    if unknown:
        raise SpecError(f"{source}: unknown keys {sorted(unknown)} (a spec has: {sorted(SPEC_KEYS)})")
    if "scene" not in spec:
        raise SpecError(f"{source}: 'scene' is missing")
    if ("grid" in spec) == ("random" in spec):
        raise SpecError(f"{source}: give 'grid' or 'random', one of them")
    spec["scene"] = os.path.abspath(os.path.join(base_dir, spec["scene"]))
    if spec.get("script"):
        spec["script"] = os.path.abspath(os.path.join(base_dir, spec["script"]))
    else:
        spec["script"] = None
    spec["seconds"] = float(spec.get("seconds", 1.0))
    if not spec["seconds"] > 0:
        raise SpecError(f"{source}: seconds must be > 0")
    spec["metrics"] = list(spec.get("metrics") or ["final_pose", "max_penetration", "max_contacts"])
    for m in spec["metrics"]:
        if m not in METRICS:
            raise SpecError(f"{source}: unknown metric '{m}' (there are: {', '.join(METRICS)})")
    if "grid" in spec:
        grid = spec["grid"]
        if not isinstance(grid, dict) or not grid or not all(isinstance(v, list) and v for v in grid.values()):
            raise SpecError(f"{source}: grid maps each key to a non-empty list of values")
        for key in grid:
            parse_key(key)
    else:
        r = spec["random"]
        if not isinstance(r, dict) or set(r) - {"n", "seed", "ranges"} or "ranges" not in r:
            raise SpecError(f"{source}: random is {{n: N, seed: S, ranges: {{KEY: [lo, hi]}}}}")
        r["n"], r["seed"] = int(r.get("n", 1)), int(r.get("seed", 0))
        for key, bounds in r["ranges"].items():
            parse_key(key)
            if not isinstance(bounds, list) or len(bounds) != 2:
                raise SpecError(f"{source}: random range of '{key}' is [lo, hi]")
            if np.shape(bounds[0]) != np.shape(bounds[1]):
                raise SpecError(f"{source}: random range of '{key}': lo and hi differ in shape")
    return spec


def plain(x):
    """numpy values as plain Python (YAML and JSON take them)."""
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    return x


def expand(spec):
    """The spec's runs, in order: [{run, seed, params: {key: value}, run_id}]. A grid's seed is 0 unless the spec
    gives random; a random run's values come from its own generator, seeded with (seed, run)."""
    runs = []
    if "grid" in spec:
        keys = list(spec["grid"])
        for i, values in enumerate(itertools.product(*(spec["grid"][k] for k in keys))):
            runs.append({"run": i, "seed": 0, "params": dict(zip(keys, values))})
    else:
        r = spec["random"]
        for i in range(r["n"]):
            rng = np.random.default_rng([r["seed"], i])
            params = {}
            for key, (lo, hi) in r["ranges"].items():
                params[key] = plain(rng.uniform(np.asarray(lo, float), np.asarray(hi, float)))
            runs.append({"run": i, "seed": r["seed"], "params": params})
    for run in runs:
        run["run_id"] = run_id(spec, run)
    return runs


def run_id(spec, run):
    """What identifies a run's result: its scenario and its parameters (a rerun skips the ids it finds)."""
    what = {"scene": spec["scene"], "script": spec["script"], "seconds": spec["seconds"],
            "device_limits": bool(spec.get("device_limits", False)), "params": run["params"], "seed": run["seed"],
            "metrics": spec["metrics"]}
    return hashlib.sha1(json.dumps(what, sort_keys=True, default=plain).encode()).hexdigest()[:16]
