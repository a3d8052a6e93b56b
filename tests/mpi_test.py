#!/usr/bin/python3
"""suite-mpi under `mpirun -np 2` on this machine (issue 16): the claims of the MPI mode, each
checked on a real job.

  layout     the ranks' CPU sets do not overlap, as launched (bound by mpirun) and unbound
             (--bind-to none: suite-mpi splits the host); each rank's threads ran inside its set
  aggregate  per point: one record per rank and one aggregate; the aggregate's work is the sum
             of the ranks', each of its repetitions the slowest rank's time, its bandwidth the
             sum moved over that time; the file is schema-valid
  refusals   more ranks than cores (a launcher mask of 2 CPUs, 3 ranks), a usage error, and one
             that only rank 1 finds (--pin=0, outside its share): exit
             2, said once, by rank 0, and no result file
  killed     a rank killed with SIGKILL mid-run: the job ends (no hang), mpirun names the rank,
             the file holds what was finished, valid, with "complete": false, and no lock file
             is left (the other rank removes it at mpirun's SIGTERM)
  stopped    SIGINT to mpirun: the ranks stop together; the file says "complete": false
  reader     suite compare and suite check read the job's file
  fem        a distributed eigenvalue (fem-eigen-dist over 2 ranks, curve and METIS partitions)
             equals the one-process fem-eigen to 1e-7 (skipped, said, if the kernel is absent)

usage: mpi_test.py SUITE SUITE_MPI SCHEMA
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

suite, suite_mpi, schema_path = sys.argv[1:4]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_WAIT_POLICY="passive")
tmp = tempfile.mkdtemp(prefix="mpi-test-")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def mpirun(args, np=2, prefix=(), timeout=180, launcher=()):
    cmd = list(prefix) + ["mpirun", "-np", str(np)] + list(launcher) + [suite_mpi] + args
    return subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)


def validate(doc, what):
    try:
        import jsonschema
    except ImportError:
        print("skip schema validation: python3-jsonschema is not installed", flush=True)
        return
    try:
        jsonschema.validate(doc, json.load(open(schema_path)))
        check(True, what + ": schema-valid")
    except jsonschema.ValidationError as e:
        check(False, what + ": schema: " + e.message[:300])


def cpu_sets(doc):
    hosts = doc["context"]["mpi"]["hosts"]
    return [set(expand(c)) for h in hosts for c in h["cpus"]]


def expand(text):
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += range(int(lo), int(hi or lo) + 1)
    return out


# --- layout and aggregate -------------------------------------------------------------------
for launcher, layout in (((), None), (("--bind-to", "none"), "split")):
    out = os.path.join(tmp, "run-%s.json" % (layout or "bound"))
    r = mpirun(["--kernel=triad,copy", "--size=16MiB", "--reps=5", "--threads=1", "--out=" + out, "--quiet"], launcher=launcher)
    what = "mpirun -np 2 %s" % " ".join(launcher)
    check(r.returncode == 0, what + ": exit 0 (%d: %s)" % (r.returncode, r.stderr.strip()[-300:]))
    if r.returncode != 0:
        continue
    doc = json.load(open(out))
    validate(doc, what)
    mpi = doc["context"]["mpi"]
    check(mpi["ranks"] == 2 and sum(len(h["ranks"]) for h in mpi["hosts"]) == 2, what + ": two ranks, each host once")
    if layout:
        check(mpi["layout"] == layout, what + ": layout %s (got %s)" % (layout, mpi["layout"]))
    sets = cpu_sets(doc)
    check(len(sets) == 2 and all(sets) and not (sets[0] & sets[1]), what + ": the ranks' CPU sets do not overlap: %s" % sets)
    check(all(h["disjoint"] for h in mpi["hosts"]), what + ": every host says disjoint")
    results = doc["results"]
    check(doc["complete"] is True and len(results) == 6, what + ": complete, 2 points x (2 ranks + aggregate)")
    for k in range(0, len(results), 3):
        ranks, agg = results[k:k + 2], results[k + 2]
        name = agg["name"]
        check([x["mpi"]["scope"] for x in results[k:k + 3]] == ["rank", "rank", "aggregate"] and
              [x["mpi"]["rank"] for x in ranks] == [0, 1], name + ": rank 0, rank 1, then the aggregate")
        for x in ranks:
            allowed = {c for t in x["pin"]["threads"] for c in t["allowed_cpus"]}
            check(allowed <= sets[x["mpi"]["rank"]], name + ": rank %d's threads ran inside its set" % x["mpi"]["rank"])
        for field in ("units", "stream_bytes", "hardware_bytes_estimate", "flops"):
            total = sum(x["work_per_repetition"][field] for x in ranks)
            check(abs(agg["work_per_repetition"][field] - total) <= 1e-9 * total, name + ": aggregate " + field + " = the ranks' sum")
        check(agg["threads"] == sum(x["threads"] for x in ranks), name + ": aggregate threads = the ranks' sum")
        slowest = [max(a, b) for a, b in zip(ranks[0]["time_s"]["samples"], ranks[1]["time_s"]["samples"])]
        check(agg["time_s"]["samples"] == slowest, name + ": each aggregate repetition is the slower rank's")
        bound = agg["work_per_repetition"]["stream_bytes"] / min(slowest) / 1e9
        check(abs(agg["bandwidth_gbps"]["stream"]["best"] - bound) <= 1e-9 * bound, name + ": aggregate GB/s = sum moved / slowest time")
        bests = [min(x["time_s"]["samples"]) for x in ranks]
        check(agg["mpi"]["slowest_rank"] == bests.index(max(bests)), name + ": the slowest rank named")
        check(abs(agg["mpi"]["spread"] - max(bests) / min(bests)) < 1e-9, name + ": spread = slowest best / fastest best")
        check(all(x["verification"]["passed"] for x in results[k:k + 3]), name + ": every record verified")

# --- the reader: the job's own file through compare and check ---------------------------------
real = os.path.join(tmp, "run-bound.json")
if os.path.exists(real):
    r = subprocess.run([suite, "compare", real], capture_output=True, text=True)
    check(r.returncode == 0 and "rank 1" in r.stdout, "suite compare on the job's file lines up its ranks (%d: %s)" %
          (r.returncode, (r.stderr or r.stdout).strip()[-200:]))
    r = subprocess.run([suite, "check", "--baseline", real, real], capture_output=True, text=True)
    check(r.returncode == 0, "suite check of the job's file against itself passes (%d: %s)" % (r.returncode, r.stderr.strip()[-200:]))

# --- refusals --------------------------------------------------------------------------------
out = os.path.join(tmp, "refused.json")
r = mpirun(["--kernel=copy", "--size=1MiB", "--out=" + out], np=3, prefix=("taskset", "-c", "0-1"), launcher=("--bind-to", "none"))
said = [l for l in r.stderr.splitlines() if l.startswith("suite-mpi: error:")]
check(r.returncode == 2 and len(said) == 1 and "would share cores" in said[0] and not os.path.exists(out),
      "3 ranks on 2 CPUs: exit 2, one line, no file (%d, %s)" % (r.returncode, said))
r = mpirun(["--kernel=cpy", "--out=" + out])
said = [l for l in r.stderr.splitlines() if l.startswith("suite-mpi: error:")]
check(r.returncode == 2 and len(said) == 1 and "did you mean 'copy'" in said[0] and not os.path.exists(out),
      "a usage error: exit 2, said once by rank 0, no file (%d, %s)" % (r.returncode, said))
# Found by rank 1 alone: each rank has one of the two CPUs, and CPU 0 is not rank 1's.
r = mpirun(["--kernel=copy", "--size=1MiB", "--pin=0", "--out=" + out])
said = [l for l in r.stderr.splitlines() if l.startswith("suite-mpi: error:")]
check(r.returncode == 2 and len(said) == 1 and said[0].startswith("suite-mpi: error: rank 1: ") and "MPI_ABORT" not in r.stderr
      and not os.path.exists(out) and not os.path.exists(out + ".lock"),
      "a usage error only rank 1 finds: exit 2, said once by rank 0 naming rank 1, no abort, no file (%d, %s)" % (r.returncode, said))


# --- a killed rank, and a stopped job ---------------------------------------------------------
def start_long(out):
    cmd = ["mpirun", "-np", "2", suite_mpi, "--kernel=copy,scale,add,triad", "--sizes=4MiB,8MiB,16MiB",
           "--min-time=0.5", "--threads=1", "--out=" + out, "--quiet"]
    p = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while time.time() < deadline and p.poll() is None:  # until the first point is in the file
        try:
            if json.load(open(out))["results"]:
                break
        except (OSError, ValueError, KeyError):
            pass
        time.sleep(0.2)
    return p


def rank_pids(mpirun_pid):
    kids = subprocess.run(["pgrep", "-P", str(mpirun_pid)], capture_output=True, text=True).stdout.split()
    return [int(k) for k in kids if "suite-mpi" in open("/proc/%s/cmdline" % k).read()]


for how in ("killed", "stopped"):
    out = os.path.join(tmp, how + ".json")
    p = start_long(out)
    if p.poll() is not None:
        check(False, how + ": the job ended before it could be stopped (%s)" % p.stderr.read()[-300:])
        continue
    t0 = time.time()
    if how == "killed":
        pids = rank_pids(p.pid)
        check(len(pids) == 2, "killed: found the two ranks' processes (%s)" % pids)
        os.kill(pids[-1], signal.SIGKILL)
    else:
        p.send_signal(signal.SIGINT)
    try:
        _, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        check(False, how + ": the job was still running 60 s later (hung)")
        continue
    check(p.returncode != 0, how + ": the job ended with a non-zero status (%d) after %.1f s" % (p.returncode, time.time() - t0))
    if how == "killed":
        check("exited on signal 9" in err, "killed: the message names the killed rank: " + " ".join(err.split())[-200:])
    else:
        check("interrupted" in err, "stopped: the ranks said they were interrupted: " + " ".join(err.split())[-200:])
    check(not os.path.exists(out + ".lock"), how + ": no lock file left behind")
    doc = json.load(open(out))
    check(doc["complete"] is False and len(doc["results"]) >= 3 and len(doc["results"]) % 3 == 0,
          how + ": the file is valid JSON with the finished points (%d records) and complete: false" % len(doc["results"]))
    validate(doc, how)

# --- distributed finite elements --------------------------------------------------------------
listed = subprocess.run([suite, "list"], capture_output=True, text=True).stdout
if "fem-eigen-dist" not in listed:
    print("skip fem: this build has no fem-eigen-dist kernel", flush=True)
else:
    mesh = "--mesh=disk:refine=4"
    serial = os.path.join(tmp, "serial.json")
    subprocess.run([suite, "--kernel=fem-eigen", mesh, "--threads=1", "--reps=1", "--out=" + serial, "--quiet"], check=True, timeout=300)
    lam = json.load(open(serial))["results"][0]["facts"]["lambda"]["value"]
    out = os.path.join(tmp, "dist.json")
    r = mpirun(["--kernel=fem-eigen-dist", "--strategy=curve,metis", "--ordering=hilbert", mesh, "--threads=1", "--reps=1",
                "--out=" + out, "--quiet"], timeout=300)
    check(r.returncode == 0, "fem-eigen-dist on 2 ranks: exit 0 (%s)" % r.stderr.strip()[-300:])
    if r.returncode == 0:
        doc = json.load(open(out))
        validate(doc, "fem-eigen-dist")
        for rec in doc["results"]:
            got = rec["facts"]["lambda"]["value"]
            check(abs(got - lam) <= 1e-7 * abs(lam), "%s %s: lambda %.12g = serial %.12g to 1e-7" %
                  (rec["name"], rec["mpi"]["scope"], got, lam))

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
