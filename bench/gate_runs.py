"""What the gate benches share (gate_noise.py, gate_reach.py): running a command, a run file
with every repetition made slower, and the quick runs made from a committed fixture."""
import copy
import json
import os
import subprocess
import sys


def run(argv, who, ok=(0,)):
    """argv run to its end; on a status not in `ok`, `who` exits naming the command and its stderr."""
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode not in ok:
        sys.exit(f"{who}: {' '.join(argv)} failed with status {r.returncode}:\n{r.stderr[-2000:]}")
    return r


def slowed(doc, f):
    """Every repetition `f` times longer, with its statistics and rates."""
    d = copy.deepcopy(doc)
    for r in d["results"]:
        t = r["time_s"]
        t["samples"] = [x * f for x in t["samples"]]
        for k in ("min", "median", "max", "mean"):
            if k in t:
                t[k] *= f
        if r.get("metric") == "bandwidth" and r.get("bandwidth_gbps"):
            for kind in r["bandwidth_gbps"].values():
                if not isinstance(kind, dict):
                    continue  # a reason beside the figures
                for k in ("best", "median"):
                    if kind.get(k) is not None:
                        kind[k] /= f
        elif r.get("latency_ns"):
            for k in ("best", "median"):
                if r["latency_ns"].get(k) is not None:
                    r["latency_ns"][k] *= f
    return d


def quick_runs(top, tmp, count, factor):
    """`count` run files in `tmp` from the first three points of the committed fixture
    vm-native.json, run i slowed by factor(i): the benches' --quick input, no measuring."""
    fixture = os.path.join(top, "tests", "fixtures", "results", "vm-native.json")
    files = []
    for i in range(count):
        with open(fixture) as f:
            doc = json.load(f)
        doc["results"] = doc["results"][:3]
        files.append(os.path.join(tmp, f"q{i}.json"))
        with open(files[-1], "w") as f:
            json.dump(slowed(doc, factor(i)), f)
    return files
