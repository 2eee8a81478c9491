"""The cost estimate against the reproduction ladder's recorded rungs, and the fit of the CPU model.

Each rung recorded under results/reproduction/<rung>/ holds the config it ran (config.yaml) and
its run.json: the CPU seconds of its simulation jobs as Snakemake's benchmark files recorded them
(core_hours, from cpu_time), the CPU it ran on and when it started, which name the machine
(cost.LADDER_MACHINES), and the engine commits its jobs ran. The estimate of a rung is its config's
jobs priced by the CPU model (cost.pull_work, cost.bed_work) at that machine's throughput, the
config's own `throughput` set aside (it was measured once, on one machine); the check also prints
what particle-steps alone at the config's `throughput` priced (the estimate before the CPU model).

Snakemake's benchmark undercounts a job's CPU: it samples the job's processes every 0.5 s for
the first 15 s, then every 30 s, and keeps the last sample (snakemake/benchmark.py,
BENCHMARK_INTERVAL 30, BENCHMARK_INTERVAL_SHORT 0.5), so a job loses the CPU it used after its last
sample: t - 15 s of a job of t = 15-45 s, 15 s on average of a longer one (a 12 d box's pulls of
20-60 s lose a third of it). The check compares the recorded CPU with the estimate less that loss
(recorded_seconds) and prints both.

    /usr/bin/python3 workflow/scripts/estimate_cost.py --check-recorded   # the table
    /usr/bin/python3 workflow/scripts/estimate_cost.py --check-recorded --markdown   # for the docs
    /usr/bin/python3 workflow/scripts/estimate_cost.py --fit-recorded     # refit the constants
"""

import json
import math
from contextlib import contextmanager
from functools import cache
from pathlib import Path

import yaml

from . import cost, paths
from .plan import plan

RECORDED = Path("results/reproduction")

# Snakemake's benchmark sampling (above): the first samples' span, then the gap between samples.
SAMPLED_DENSELY, SAMPLE_GAP = 15.0, 30.0

# The constants --fit-recorded fits, with the scale each is fitted in.
FITTED = ("PULL_START_STEPS", "PULL_TIME_STEPS", *(f"machine {i + 1}" for i in range(len(cost.LADDER_MACHINES))))


def lost_to_sampling(seconds):
    """Expected CPU seconds a job of `seconds` loses from its benchmark's cpu_time (fully busy)."""
    if seconds < SAMPLED_DENSELY:
        return 0.25                                 # half the dense samples' gap
    return min(seconds - SAMPLED_DENSELY, SAMPLE_GAP / 2)


def machine_index(started, cpu="Intel(R) Xeon(R) Processor", machines=None):
    """Which of cost.LADDER_MACHINES a rung ran on: the last whose CPU name is in `cpu` (run.json's
    machine.cpu) and whose date is on or before `started` (an ISO date)."""
    found = None
    for i, (name, since, _) in enumerate(machines or cost.LADDER_MACHINES):
        if name in cpu and started[:10] >= since:
            found = i
    if found is None:
        raise ValueError(f"a rung started {started} on {cpu!r}: no recorded machine matches")
    return found


def machine_throughput(started, cpu="Intel(R) Xeon(R) Processor", machines=None):
    """The throughput of the recorded machine a rung ran on (machine_index)."""
    machines = machines or cost.LADDER_MACHINES
    return machines[machine_index(started, cpu, machines)][2]


def job_seconds(config, throughput, p=None):
    """{job: estimated CPU seconds} of a config's simulation jobs (its plan p) at `throughput` on its
    threads."""
    p = p or plan(config)
    threads = int(config.get("threads", 1))
    work = {paths.job_name("beds", k): cost.bed_work(b, config) for k, b in p.beds.items()}
    work.update({paths.job_name("columns", k): cost.column_work(b, config) for k, b in p.columns.items()})
    work.update({paths.job_name("pulls", k): cost.pull_work(q, config) for k, q in p.pulls.items()})
    return {job: w / throughput * threads for job, w in work.items()}


@cache
def _load(rung_dir):
    """(config, plan) of a recorded rung; kept, as the fit prices each rung many times."""
    config = yaml.safe_load((rung_dir / "config.yaml").read_text())
    config.setdefault("threads", 1)
    config.setdefault("throughput", 1.0e7)
    return config, plan(config)


def recorded_rungs(root=RECORDED):
    """[(name, rung directory, run.json)] of every rung with a run.json, by name."""
    return [(d.name, d, json.loads((d / "run.json").read_text()))
            for d in sorted(Path(root).iterdir()) if (d / "run.json").is_file()]


def check_rung(rung_dir, run, machines=None):
    """A recorded rung's estimate against its measurement: a dict of core-hours (estimate: the
    CPU model; recorded_estimate: less the benchmark's sampling loss; measured: run.json's),
    ratio = measured / recorded_estimate, steps_ratio = measured / the particle-steps alone at the
    config's throughput (the estimate before the CPU model), the machine (its index in
    LADDER_MACHINES) and the engine commits that ran the jobs."""
    config, p = _load(Path(rung_dir))
    started, cpu = run.get("started") or run["date"], (run.get("machine") or {}).get("cpu", "Intel")
    machines = machines or cost.LADDER_MACHINES
    machine = machine_index(started, cpu, machines)
    throughput = machines[machine][2]
    seconds = job_seconds(config, throughput, p)
    steps = sum(cost.expected_bed_cost(b, config) for b in p.beds.values())
    steps += sum(cost.expected_column_cost(b, config) for b in p.columns.values())
    steps += sum(cost.expected_pull_cost(q, config) for q in p.pulls.values())
    steps_hours = steps / float(config["throughput"]) * int(config["threads"]) / 3600
    estimate = sum(seconds.values())
    recorded = sum(t - min(t, lost_to_sampling(t)) for t in seconds.values())
    at_config = estimate * throughput / float(config["throughput"])
    measured = float(run["core_hours"]) * 3600.0
    return {"rung": rung_dir.name, "throughput": throughput, "jobs": len(seconds), "recorded_jobs": run["jobs"],
            "at_config": at_config / 3600, "estimate": estimate / 3600, "recorded_estimate": recorded / 3600,
            "measured": measured / 3600, "ratio": measured / recorded, "machine": machine,
            "steps_at_config": steps_hours, "steps_ratio": measured / 3600 / steps_hours,
            "engines": dict(run.get("engine_commits") or {})}


def check(root=RECORDED, machines=None):
    """check_rung of every recorded rung."""
    return [check_rung(d, run, machines) for _, d, run in recorded_rungs(root)]


def partial_rung(rung_dir, config_path):
    """Per landed job of a rung in pieces (<rung>/pieces/benchmarks/): its recorded
    CPU seconds and its estimate at a throughput of 1 (work in particle-step equivalents), as
    [(job, cpu seconds, wall seconds, work)]. A rung's later parts may land their pieces in the
    same folder under another config: only the jobs `config_path` plans are listed."""
    config = yaml.safe_load(Path(config_path).read_text())
    config.setdefault("threads", 1)
    work = job_seconds(config, 1.0)
    rows = []
    for tsv in sorted((Path(rung_dir) / "pieces" / "benchmarks").glob("**/*.tsv")):
        header, values = tsv.read_text().splitlines()[:2]
        record = dict(zip(header.split("\t"), values.split("\t")))
        job = str(tsv.relative_to(Path(rung_dir) / "pieces" / "benchmarks"))[:-len(".tsv")]
        if job not in work:
            continue
        rows.append((job, float(record["cpu_time"]), float(record["s"]), work[job]))
    return rows


@contextmanager
def constants(values):
    """The cost model with the FITTED constants set to `values` (machines: LADDER_MACHINES's rates)."""
    names = FITTED[:2]
    saved = [getattr(cost, n) for n in names] + [cost.LADDER_MACHINES]
    try:
        for n, v in zip(names, values[:2]):
            setattr(cost, n, v)
        cost.LADDER_MACHINES = tuple((cpu, since, rate) for (cpu, since, _), rate in zip(saved[-1], values[2:]))
        yield
    finally:
        for n, v in zip(names, saved[:2]):
            setattr(cost, n, v)
        cost.LADDER_MACHINES = saved[-1]


def fit(root=RECORDED, leave_out=None, minimax=True):
    """The FITTED constants that best match the recorded rungs, and the ratios they leave:
    (values, {rung: ratio}). Least squares of log(ratio) first, then (minimax) the largest
    |log(ratio)| made as small as it goes (the promise is a bound on every rung, not an average).
    leave_out: a rung left out of the fit, its ratio then a prediction."""
    import numpy as np
    from scipy.optimize import least_squares, minimize

    rungs = [r for r in recorded_rungs(root) if r[0] != leave_out]
    start = [cost.PULL_START_STEPS, cost.PULL_TIME_STEPS, *(rate for _, _, rate in cost.LADDER_MACHINES)]
    scale = np.array([1e3, 1e2, *[1e7] * len(cost.LADDER_MACHINES)])

    def residuals(x):
        with constants(list(np.abs(x) * scale)):
            return np.array([math.log(check_rung(d, run)["ratio"]) for _, d, run in rungs])

    x = least_squares(residuals, np.array(start) / scale, bounds=(1e-6, np.inf)).x
    if minimax:
        x = minimize(lambda y: np.abs(residuals(y)).max(), x, method="Nelder-Mead",
                     options={"xatol": 1e-4, "fatol": 1e-5, "maxiter": 2000}).x
    values = [float(v) for v in np.abs(x) * scale]
    with constants(values):
        return values, {name: check_rung(d, run)["ratio"] for name, d, run in recorded_rungs(root)}


def leave_one_out(root=RECORDED):
    """{rung: its ratio predicted by the least-squares fit to the other rungs} (a few seconds each);
    None for a rung alone on its machine (its rate is then not fitted: nothing predicts it)."""
    rungs = recorded_rungs(root)
    machine = {name: check_rung(d, run)["machine"] for name, d, run in rungs}
    alone = {m for m in machine.values() if list(machine.values()).count(m) == 1}
    return {name: None if machine[name] in alone else fit(root, leave_out=name, minimax=False)[1][name]
            for name, _, _ in rungs}


def print_check(rows, out):
    print("rung                        machine's     jobs  estimate  less the   measured  measured /", file=out)
    print("                            throughput           (CPU)   sampling            estimate", file=out)
    for r in rows:
        print(f"{r['rung']:27s} {r['throughput']:10.3g} {r['jobs']:6d} {r['estimate']:9.3f} "
              f"{r['recorded_estimate']:9.3f} {r['measured']:9.3f} {r['ratio']:9.2f}", file=out)
    worst = max(rows, key=lambda r: abs(math.log(r["ratio"])))
    print(f"core-hours; {len(rows)} rungs, measured / estimate {min(r['ratio'] for r in rows):.2f}-"
          f"{max(r['ratio'] for r in rows):.2f} (farthest: {worst['rung']})", file=out)


def engines_text(engines):
    """A rung's engine commits as text: the commit, or the commits with their jobs, most first."""
    if len(engines) == 1:
        return next(iter(engines))
    ranked = sorted(engines.items(), key=lambda kv: -kv[1])
    text = ", ".join(f"{c} ({n})" for c, n in ranked[:3])
    return text + (f", {len(ranked) - 3} more ({sum(n for _, n in ranked[3:])})" if len(ranked) > 3 else "")


def print_markdown(rows, out, loo=None):
    """The check as a markdown table (the docs' table): per rung its machine, engine(s), the
    estimate before the CPU model (particle-steps at the config's throughput) and the CPU model's,
    the measured core-hours and both ratios; loo: leave_one_out's predictions, a column."""
    head = ("| rung | machine | engine (jobs) | particle-steps at the config's throughput | measured / that "
            "| CPU model (less sampling) | measured | measured / CPU model |")
    if loo is not None:
        head += " left out of the fit |"
    print(head, file=out)
    print("|" + "---|" * (head.count("|") - 1), file=out)
    for r in rows:
        line = (f"| {r['rung']} | {r['machine'] + 1} | {engines_text(r['engines'])} | {r['steps_at_config']:.3f} | "
                f"{r['steps_ratio']:.2f} | {r['estimate']:.3f} ({r['recorded_estimate']:.3f}) | {r['measured']:.3f} | "
                f"**{r['ratio']:.2f}** |")
        if loo is not None:
            pred = loo.get(r["rung"])
            line += f" {pred:.2f} |" if pred is not None else " (alone on its machine) |"
        print(line, file=out)
