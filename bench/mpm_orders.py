#!/usr/bin/python3
"""The MPM kernels by particle and grid order: what sorting the particles buys, sort cost included.

Four parts, each from `suite` runs on this machine (nothing is timed here):
  flow      the dam break (`suite mpm --case=dam-break`), one thread, particles seeded (what a code
            that seeds and never sorts has: the baseline), shuffled (the worst case), sorted every
            K steps and dynamic, R rounds: particle-steps/s over the whole run and in windows of
            the flow, sort cost included, and how the gain over seeded grows as the water mixes
            (mpm_flow.png).
  sort      R rounds of mpm-step on one thread (the elastic dam collapse: the particles barely
            move), --particles=seeded,shuffled,sorted,dynamic on every grid ordering in one run:
            per round each point's particle-steps/s against seeded particles on the natural grid;
            the median over the rounds. One repetition is K = --sort-every
            steps and the sort (and the renumbering, for dynamic) that falls due after them, so the
            sort's cost is inside every timing.
  every     mpm-step, sorted particles on the Hilbert grid, at each K of --every: the K to choose.
  auto      --sort-every=auto against the best fixed K of a sweep (--auto-every), sorted and dynamic,
            on the natural and the Hilbert grid, the dam break and the elastic collapse
            (`suite mpm`, one thread, R interleaved rounds: every run of a round before the next
            round): particle-steps/s over the whole run and window by window, sort cost included,
            each against seeded particles and against the best K; the medians over the rounds.
  p2g       mpm-p2g's scatter strategies at every thread count and grid ordering, with the node
            updates each had to synchronise (the record's facts).

Usage: bench/mpm_orders.py [--rounds 3] [--mesh box:56,56,56] [--flow-mesh box:40,40,40] [--out results/bench] [--quick]
Writes OUT/mpm_orders.{json,md} (with --parts flow alone: OUT/mpm_flow.{json,md}; auto alone: OUT/mpm_auto.{json,md}) and OUT/mpm_flow.png; --quick: small grids, one round, a check in a minute that it all runs.
"""
import argparse
import datetime
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plots"))
from safe_output import write_text  # noqa: E402  (the suite's one output policy)

here = os.path.dirname(os.path.abspath(__file__))
top = os.path.dirname(here)
p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--suite", default=os.path.join(top, "suite"))
p.add_argument("--out", default=os.path.join(top, "results", "bench"))
p.add_argument("--rounds", type=int, default=3)
p.add_argument("--mesh", default="box:56,56,56", help="the grid (default: 1.05 M tetrahedra, 0.54 M particles, 82 MB of particle arrays)")
p.add_argument("--orderings", default="natural,random,morton,hilbert")
p.add_argument("--every", default="1,5,20,50,100", help="the K of the 'every' part")
p.add_argument("--sort-every", default="5", help="K of the 'sort' part (5: the fastest of the 'every' part on the development VM)")
p.add_argument("--threads", default="1,2", help="thread counts of the 'p2g' part")
p.add_argument("--parts", default="flow,sort,every,auto,p2g")
p.add_argument("--flow-mesh", default="box:40,40,40", help="the dam break's grid (default: 0.28 M particles, 44 MB of particle arrays)")
p.add_argument("--flow-steps", type=int, default=2500, help="steps of the dam break (default 2500: about 0.9 s, the water has hit the far wall and mixed)")
p.add_argument("--flow-every", default="5,20,50,100", help="the K tried for the flow part's sorted runs; the fastest is used for sorted and dynamic")
p.add_argument("--windows", type=int, default=10, help="windows of the flow the rates are taken in")
p.add_argument("--auto-mesh", default="box:24,24,24", help="the auto part's grid")
p.add_argument("--auto-steps", type=int, default=1000, help="steps of each run of the auto part")
p.add_argument("--auto-every", default="5,20,50", help="the fixed K the auto part sweeps")
p.add_argument("--auto-cases", default="dam-break,dam-collapse")
p.add_argument("--auto-grids", default="natural,hilbert")
p.add_argument("--auto-stat", choices=("median", "fastest"), default="median",
               help="the auto part's statistic: median (of the rounds' ratios) or fastest (each window of the run at its "
                    "fastest round, the run's time the sum of those: a slow state of a shared machine only ever slows a run, "
                    "and lasts seconds, so that no whole run of a few seconds may escape it)")
p.add_argument("--quick", action="store_true")
a = p.parse_args()
if a.quick:
    a.rounds, a.mesh, a.every, a.flow_mesh, a.flow_steps, a.flow_every = 1, "box:12,12,12", "1,20", "box:10,10,10", 400, "5,20"
    a.auto_mesh, a.auto_steps, a.auto_every = "box:8,8,8", 100, "5,20"
parts = a.parts.split(",")
orderings = a.orderings.split(",")
tmp = tempfile.mkdtemp(prefix="mpm-orders-")


def suite(args):
    out = os.path.join(tmp, "r.json")
    argv = [a.suite] + args + ["--out", out, "--quiet"]
    print("  " + " ".join(argv[:1] + args), file=sys.stderr, flush=True)
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"mpm_orders: {' '.join(argv)} failed ({r.returncode}): {r.stderr.strip()[-400:]}")
    with open(out) as f:
        return json.load(f)


def rate(rec):
    return rec["units_per_second_best"]


def fact(rec, name):
    f = (rec.get("facts") or {}).get(name)
    return f["value"] if f else None


report = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "command": sys.argv, "rounds": a.rounds, "mesh": a.mesh}
lines = [f"# MPM by particle and grid order ({report['date']}, {a.rounds} round(s)" + ("" if parts in (["flow"], ["auto"]) else f", {a.mesh}") + ")", ""]

def flow_run(particles, sort_every, directory, case="dam-break", mesh=None, steps=None, ordering="natural"):
    """One run of suite mpm; returns the rows of its front.csv as dicts (numbers as floats) and its mpm.json."""
    import csv
    argv = [a.suite, "mpm", f"--case={case}", f"--mesh={mesh or a.flow_mesh}", f"--ordering={ordering}", f"--particles={particles}",
            f"--steps={steps or a.flow_steps}", "--vtk-every=0", "--no-png", "--quiet", "--threads=1", f"--out={directory}"] + (
            [f"--sort-every={sort_every}"] if particles in ("sorted", "dynamic") else [])
    print("  " + " ".join(argv), file=sys.stderr, flush=True)
    r = subprocess.run(argv, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"mpm_orders: {' '.join(argv)} failed ({r.returncode}): {r.stderr.strip()[-400:]}")
    with open(os.path.join(directory, "front.csv"), newline="") as f:
        rows = [{k: (float(v) if k != "reordered" else v) if v != "" else None for k, v in row.items()} for row in csv.DictReader(f)]
    with open(os.path.join(directory, "mpm.json")) as f:
        return rows, json.load(f)


if "flow" in parts:
    orders = ["seeded", "shuffled", "sorted", "dynamic"]
    window_rates = {o: [] for o in orders}  # per round: the rate in each window
    overall = {o: [] for o in orders}
    order_decay = {}
    edges = [round(i * a.flow_steps / a.windows) for i in range(a.windows + 1)]
    # K by measurement: sorted particles at each K once, the fastest over the whole flow.
    k_rates = {}
    for k in a.flow_every.split(","):
        rows, doc = flow_run("sorted", k, os.path.join(tmp, f"flow-k{k}"))
        k_rates[k] = doc["timing"]["particle_steps_per_second"]
    a.flow_sort_every = max(k_rates, key=k_rates.get)
    report["flow_every"] = k_rates
    for rnd in range(a.rounds):
        for o in orders:
            rows, doc = flow_run(o, a.flow_sort_every, os.path.join(tmp, f"flow-{o}-{rnd}"))
            n = doc["counts"]["particles"]
            overall[o].append(doc["timing"]["particle_steps_per_second"])
            window_rates[o].append([n * (edges[i + 1] - edges[i]) / (rows[edges[i + 1]]["stepping_seconds"] - rows[edges[i]]["stepping_seconds"])
                                    for i in range(a.windows)])
            if rnd == 0:
                order_decay[o] = [rows[e]["mean_curve_gap"] for e in edges]
                if o == "seeded":
                    report["flow_particles"] = n
                    report["flow_time"] = [rows[e]["time"] for e in edges]
                    report["flow_front"] = [rows[e]["front"] for e in edges]
    # Gains against seeded: per round and window, then the median over the rounds.
    gain = {o: [statistics.median(window_rates[o][r][w] / window_rates["seeded"][r][w] for r in range(a.rounds)) for w in range(a.windows)]
            for o in orders}
    total_gain = {o: statistics.median(overall[o][r] / overall["seeded"][r] for r in range(a.rounds)) for o in orders}
    report["flow"] = {"mesh": a.flow_mesh, "steps": a.flow_steps, "sort_every": a.flow_sort_every, "window_edges": edges,
                      "particle_steps_per_s": {o: statistics.median(overall[o]) for o in orders}, "gain_vs_seeded": total_gain,
                      "window_gain_vs_seeded": gain, "mean_curve_gap_at_edges": order_decay}
    lines += [f"## The dam break ({a.flow_mesh}, {report['flow_particles']} particles, {a.flow_steps} steps to "
              f"t = {report['flow_time'][-1]:.2f} s, one thread, K = {a.flow_sort_every}, sort cost included)", "",
              "| particles | particle-steps/s | against seeded | first tenth of the steps | last tenth |", "|---|---|---|---|---|"]
    for o in orders:
        label = o + (" (worst case)" if o == "shuffled" else " (the baseline)" if o == "seeded" else "")
        lines.append(f"| {label} | {statistics.median(overall[o]) / 1e6:.2f} M | {total_gain[o]:.2f}x | {gain[o][0]:.2f}x | {gain[o][-1]:.2f}x |")
    lines += ["", "K by measurement (sorted, one run each, particle-steps/s): " + ", ".join(f"K = {k}: {v / 1e6:.2f} M" for k, v in k_rates.items()), ""]
    lines += ["How far the seeded order decays (the mean distance along the curve between consecutive particles' elements) at the windows' edges: "
              + ", ".join(f"{v:.0f}" for v in order_decay["seeded"]) + "; the front at them (m): "
              + ", ".join(f"{v:.2f}" for v in report["flow_front"]), ""]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from safe_output import save_figure  # noqa: E402
        mid = [(edges[i] + edges[i + 1]) / 2 for i in range(a.windows)]
        fig, ax = plt.subplots(figsize=(7, 4.5), dpi=100)
        for o, colour in (("sorted", "tab:green"), ("dynamic", "tab:blue"), ("shuffled", "tab:red")):
            ax.plot(mid, gain[o], marker="o", color=colour, label=o + (f" every {a.flow_sort_every} steps" if o != "shuffled" else " (worst case)"))
        ax.axhline(1, color="grey", linestyle="--", linewidth=1, label="seeded, never reordered (the baseline)")
        ax.set_xlabel("step of the dam break")
        ax.set_ylabel("particle-steps/s against seeded, in that window")
        ax.set_title(f"Re-sorting as the water mixes: {a.flow_mesh}, {report['flow_particles']} particles, one thread", fontsize=10)
        ax.legend(fontsize=8)
        fig.tight_layout()
        os.makedirs(a.out, exist_ok=True)
        save_figure(fig, os.path.join(a.out, "mpm_flow" + ("_quick" if a.quick else "") + ".png"))
        plt.close(fig)
    except ImportError as e:
        print(f"mpm_orders: no figure: matplotlib is missing ({e.name})", file=sys.stderr)

if "sort" in parts:
    ratio, rates, facts = {}, {}, {}
    for r in range(a.rounds):
        res = suite(["--kernel=mpm-step", f"--mesh={a.mesh}", f"--ordering={a.orderings}", "--threads=1", f"--sort-every={a.sort_every}", "--reps=5"]
                    + (["--probe-caches"] if r == 0 else []))
        if r == 0:
            report["measured_llc_bytes"] = (res["context"].get("caches_measured") or {}).get("last_level_total_bytes")
        by = {(rec["ordering"], rec["variant"]): rec for rec in res["results"]}
        base = rate(by[("natural", "seeded")])
        for key, rec in by.items():
            ratio.setdefault(key, []).append(rate(rec) / base)
            rates.setdefault(key, []).append(rate(rec))
            facts[key] = {"particles": fact(rec, "particles"), "active_nodes": fact(rec, "active-nodes"), "footprint_bytes": rec["size"]["footprint_bytes"]}
    report["sort"] = {f"{o}/{v}": {"speed_vs_seeded_natural": statistics.median(ratio[(o, v)]), "per_round": ratio[(o, v)],
                                   "particle_steps_per_s": statistics.median(rates[(o, v)]), **facts[(o, v)]} for (o, v) in ratio}
    any_key = next(iter(facts))
    np_, fp = facts[any_key]["particles"], facts[any_key]["footprint_bytes"]
    llc = report.get("measured_llc_bytes")
    lines += ["## mpm-step (elastic dam collapse), one thread: speed against seeded particles on the natural grid", "",
              f"{np_:.0f} particles; all arrays {fp / 1e6:.0f} MB" + (f", {fp / llc:.0f}x the measured last level ({llc / 1e6:.1f} MB)" if llc else "")
              + f"; K = {a.sort_every}, sort cost included", "",
              "| grid | seeded | shuffled (worst case) | sorted | dynamic | sorted: particle-steps/s | sorted: node-steps/s |", "|---|---|---|---|---|---|---|"]
    for o in orderings:
        cells = [f"{statistics.median(ratio[(o, v)]):.2f}x" for v in ("seeded", "shuffled", "sorted", "dynamic")]
        r, f = statistics.median(rates[(o, 'sorted')]), facts[(o, 'sorted')]
        nodes = f"{r * f['active_nodes'] / f['particles'] / 1e6:.2f} M" if f["active_nodes"] else "n/a"
        lines.append(f"| {o} | " + " | ".join(cells) + f" | {r / 1e6:.2f} M | {nodes} |")
    lines.append("")

if "every" in parts:
    per_k = {}
    for r in range(a.rounds):
        for k in a.every.split(","):
            res = suite(["--kernel=mpm-step", f"--mesh={a.mesh}", "--ordering=hilbert", "--particles=sorted", "--threads=1", f"--sort-every={k}", "--reps=5"])
            per_k.setdefault(k, []).append(rate(res["results"][0]))
    report["every"] = {k: {"particle_steps_per_s_median": statistics.median(v), "per_round": v} for k, v in per_k.items()}
    lines += ["## Sorting every K steps (sorted particles, Hilbert grid, one thread, sort included)", "",
              "| K | particle-steps/s |", "|---|---|"]
    for k, v in per_k.items():
        lines.append(f"| {k} | {statistics.median(v) / 1e6:.2f} M |")
    lines.append("")

if "auto" in parts:
    ks = a.auto_every.split(",")
    windows = a.windows
    edges = [round(i * a.auto_steps / windows) for i in range(windows + 1)]
    configs = [("seeded", None)] + [(o, k) for o in ("sorted", "dynamic") for k in ks + ["auto"]]
    whole, win, counts, particles = {}, {}, {}, {}
    for rnd in range(a.rounds):  # interleaved: every run of a round before the next round
        for case in a.auto_cases.split(","):
            for grid in a.auto_grids.split(","):
                for o, k in configs:
                    rows, doc = flow_run(o, k, os.path.join(tmp, f"auto-{case}-{grid}-{o}-{k}-{rnd}"), case, a.auto_mesh, a.auto_steps, grid)
                    n = doc["counts"]["particles"]
                    key = (case, grid, o, k)
                    whole.setdefault(key, []).append(doc["timing"]["particle_steps_per_second"])
                    win.setdefault(key, []).append([n * (edges[i + 1] - edges[i]) / (rows[edges[i + 1]]["stepping_seconds"] - rows[edges[i]]["stepping_seconds"])
                                                    for i in range(windows)])
                    counts[key] = (doc["reorderings"] or {}).get("count")
                    particles[key] = n
    med = statistics.median
    fastest = a.auto_stat == "fastest"

    def composed(key, first=0):
        """The rate of windows `first`.. each at its fastest round: their steps over the sum of their shortest times."""
        steps = [(edges[w + 1] - edges[w]) * particles[key] for w in range(first, windows)]
        return sum(steps) / sum(min(steps[i] / win[key][r][first + i] for r in range(a.rounds)) for i in range(len(steps)))
    out = {}
    how = (f"the fastest of {a.rounds} interleaved round(s)" if fastest else f"median of {a.rounds} interleaved round(s)")
    lines += [f"## --sort-every=auto against the best fixed K ({a.auto_mesh}, {a.auto_steps} steps, one thread, sort cost included, "
              f"{how})", "",
              ("Each window of a setting is taken at its fastest round, and its whole-run rate is the run's steps over the sum of those "
               "windows' times; the ratios are of those; "
               if fastest else "Each ratio is taken within a round and the median over the rounds is shown; ") +
              f"the best K is the fixed K (of {a.auto_every}) with the highest {'fastest' if fastest else 'median'} whole-run rate. "
              "\"Second half\": the windows after the middle step (the mixed flow).", "",
              "| case | grid | particles | seeded | best K | auto | auto / best K | auto / seeded | second half: auto / best K | auto / seeded | reorderings (auto, best K) |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    half = windows // 2
    for case in a.auto_cases.split(","):
        for grid in a.auto_grids.split(","):
            base = (case, grid, "seeded", None)
            for o in ("sorted", "dynamic"):
                rate_of = (lambda key: composed(key)) if fastest else (lambda key: med(whole[key]))
                best = max(ks, key=lambda k: rate_of((case, grid, o, k)))
                au, bk = (case, grid, o, "auto"), (case, grid, o, best)
                if fastest:
                    ratio = lambda x, y: composed(x) / composed(y)
                    second = lambda x, y: composed(x, half) / composed(y, half)
                    by_window = lambda x, y: [max(win[x][r][w] for r in range(a.rounds)) / max(win[y][r][w] for r in range(a.rounds))
                                              for w in range(windows)]
                else:
                    ratio = lambda x, y: med(whole[x][r] / whole[y][r] for r in range(a.rounds))
                    second = lambda x, y: med(sum(win[x][r][half:]) / sum(win[y][r][half:]) for r in range(a.rounds))
                    by_window = lambda x, y: [med(win[x][r][w] / win[y][r][w] for r in range(a.rounds)) for w in range(windows)]
                per_window = {"auto_vs_best": by_window(au, bk), "auto_vs_seeded": by_window(au, base)}
                out[f"{case}/{grid}/{o}"] = {"best_k": best, "rates": {str(k): rate_of((case, grid, o, k)) for k in ks + ["auto"]},
                                             "rounds": {str(k): whole[(case, grid, o, k)] for k in ks + ["auto"]},
                                             "window_rates": {str(k): win[(case, grid, o, k)] for k in ks + ["auto"]},
                                             "seeded_window_rates": win[base],
                                             "seeded": rate_of(base), "auto_vs_best": ratio(au, bk), "auto_vs_seeded": ratio(au, base),
                                             "second_half_auto_vs_best": second(au, bk), "second_half_auto_vs_seeded": second(au, base),
                                             "windows": per_window, "reorderings": {"auto": counts[au], "best_k": counts[bk]},
                                             "per_round": {"auto": whole[au], "best_k": whole[bk], "seeded": whole[base]}}
                e = out[f"{case}/{grid}/{o}"]
                lines.append(f"| {case} | {grid} | {o} | {e['seeded'] / 1e6:.2f} M | K = {best}: {e['rates'][best] / 1e6:.2f} M | {e['rates']['auto'] / 1e6:.2f} M | "
                             f"{e['auto_vs_best']:.3f}x | {e['auto_vs_seeded']:.3f}x | {e['second_half_auto_vs_best']:.3f}x | {e['second_half_auto_vs_seeded']:.3f}x | "
                             f"{counts[au]}, {counts[bk]} |")
    lines += ["", "Window by window (auto against the best K; auto against seeded), per tenth of the run:", ""]
    for key, e in out.items():
        lines.append(f"- {key}: " + ", ".join(f"{x:.2f}" for x in e["windows"]["auto_vs_best"]) + "; "
                     + ", ".join(f"{x:.2f}" for x in e["windows"]["auto_vs_seeded"]))
    lines.append("")
    report["auto"] = {"mesh": a.auto_mesh, "steps": a.auto_steps, "every": ks, "window_edges": edges, "statistic": a.auto_stat,
                      "cases": out}

if "p2g" in parts:
    res = suite(["--kernel=mpm-p2g", f"--mesh={a.mesh}", f"--ordering={a.orderings}", f"--threads={a.threads}", "--reps=5"])
    rows = []
    for rec in res["results"]:
        rows.append({"ordering": rec["ordering"], "strategy": rec["variant"], "threads": rec["threads"], "particles_per_s": rate(rec),
                     "synchronised": fact(rec, "synchronised"), "colours": fact(rec, "colours"), "shared_nodes": fact(rec, "shared-nodes")})
    report["p2g"] = rows
    lines += ["## mpm-p2g by strategy (particles sorted along the curve)", "",
              "| grid | strategy | threads | particles/s | synchronised node updates | colours / shared nodes |", "|---|---|---|---|---|---|"]
    for r in rows:
        extra = r["colours"] if r["colours"] is not None else r["shared_nodes"] if r["shared_nodes"] is not None else ""
        lines.append(f"| {r['ordering']} | {r['strategy']} | {r['threads']} | {r['particles_per_s'] / 1e6:.2f} M | {r['synchronised']:.0f} | {extra} |")
    lines.append("")

os.makedirs(a.out, exist_ok=True)
# The dam break alone (--parts flow) has files of its own, beside the kernels' tables.
stem = os.path.join(a.out, {"flow": "mpm_flow", "auto": "mpm_auto"}.get(",".join(parts), "mpm_orders") + ("_quick" if a.quick else ""))
write_text(stem + ".json", json.dumps(report, indent=1) + "\n")
write_text(stem + ".md", "\n".join(lines) + "\n")
print("\n".join(lines))
