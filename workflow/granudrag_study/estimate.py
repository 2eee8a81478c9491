"""Job count and estimated cost of a study config, from measured throughput.

    /usr/bin/python3 -m granudrag_study.estimate config/paper.yaml [--throughput PS] [--cores N] [--by-sweep]
        [--by-figure] [--measure [--grains G] [--binary build/granudrag]]
    /usr/bin/python3 -m granudrag_study.estimate --check-recorded [--markdown [--leave-one-out]]
    /usr/bin/python3 -m granudrag_study.estimate --fit-recorded     # refit the CPU model

Cost model (granudrag_study.cost): a pull costs grains x travel / (V dt)
particle-steps, a pour at most grains x max_settle_time / dt, and is expected to stop
at the kinetic-energy threshold as measured (undamped pours to 1e-6 after a time
proportional to the column's height, damped frictional beds after about a quarter of
faithful.yaml's limits; others run to the limit). dt is the config's, or granudrag's
default (analysis.core.physics.default_dt, proportional to K_n^-0.4). A pull's CPU is its
particle-steps plus, per grain, a start and a cost per unit of simulated time (the CPU
model, fitted to the reproduction ladder's recorded rungs: granudrag_study.recorded).
Core-hours = that work / throughput x threads, where throughput is the particle-steps
per second of a pull's steps, one job on `threads` threads (the config's `throughput`,
measured with `granudrag pull`, which prints it).
Wall time on N cores (default: this machine's) assumes N / threads jobs at a time, perfectly
packed; on fewer cores than a job's threads, the jobs run one at a time on N threads at the
throughput's rate per thread (the core-hours over N), never at the rate of the job's own node.

--measure replaces the config's throughput by one measured here on the workload the jobs run:
`granudrag pour` settles a bed of G grains (default: the smallest system's, at most 70,000;
the column density of the benchmark bed, 19.25 grains per d^2, K_n = 2e5), then `granudrag
pull` drags a D = 2 intruder through it at V = 1 for 1,000 steps, both on min(threads, cores
here) threads; the slower of the two rates is taken (the cost of a step depends on the
contacts, not on K_n).
For a job with more threads than this machine has, the measured per-core rate is scaled by
the threads at PARALLEL_EFFICIENCY (an assumption, stated in the output; measure on the
cluster's nodes to replace it).
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import yaml

import granudrag_study as study

from .breakdown import by_figure, core_hours
from .cost import POUR_STEP_COST
from .recorded import RECORDED

# Assumed efficiency of a job's OpenMP threads beyond those measured here (2 threads: 0.95-0.97
# on bench/compare_lammps.sh's beds).
PARALLEL_EFFICIENCY = 0.8
# The most threads any rate here was measured on, and the share of the loop that stays serial
# there (cell counting, checkpoint writing: 1-2.5 % at 2 threads, docs/engine.md, "Threads").
# Amdahl's law on that share bounds what more threads can give (amdahl_efficiency); memory
# bandwidth and NUMA placement lower it further, by an amount not measured here.
MEASURED_THREADS = 2
SERIAL_SHARE = (0.01, 0.025)


def amdahl_efficiency(threads, serial_share, measured_threads=MEASURED_THREADS):
    """Efficiency of `threads` threads relative to the per-thread rate measured on
    `measured_threads`, where `serial_share` of that measured loop stays serial (Amdahl's law):
    T_n = s T_m + (1 - s) T_m m / n, efficiency m T_m / (n T_n) = m / (n s + m (1 - s))."""
    m, n, s = measured_threads, threads, serial_share
    return m / (n * s + m * (1.0 - s))


# Grains per d^2 of bed area in the measuring bed: bench/compare_lammps.sh's 7.7k bed.
COLUMN_DENSITY = 19.25
MEASURE_STEPS, MEASURE_DT = 1000, 5e-4


def _run(cmd):
    print(f"measuring: {' '.join(cmd)}", file=sys.stderr)
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    except FileNotFoundError:
        sys.exit(f"estimate_cost: no granudrag at {cmd[0]}: build it (cmake --build build) or pass --binary")
    except subprocess.CalledProcessError as exc:
        sys.exit(f"estimate_cost: {' '.join(cmd)} failed:\n{exc.stderr.strip()}")


def measure_throughput(binary, grains, threads):
    """(particle-steps/s of one job on `threads` threads, how it was obtained), from a pull
    through a bed poured here."""
    here = min(threads, os.cpu_count() or 1)
    side = max(8.0, (grains / COLUMN_DENSITY) ** 0.5)
    with tempfile.TemporaryDirectory() as tmp:
        bed, run = str(Path(tmp) / "bed.h5"), str(Path(tmp) / "run.h5")
        poured = _run([str(binary), "pour", "--output", bed, "--grains", str(grains), "--lx", f"{side:.6g}",
              "--ly", f"{side:.6g}", "--intruder_diameter", "2", "--depth", "5", "--kn", "2e5",
              "--dt", str(MEASURE_DT), "--ke_threshold", "1e-4", "--max_settle_time", "10",
              "--threads", str(here), "--quiet"])
        out = _run([str(binary), "pull", "--bed", bed, "--output", run, "--speed", "1",
                    "--distance", repr((MEASURE_STEPS - 0.5) * MEASURE_DT), "--snapshots", "0",
                    "--threads", str(here), "--quiet"])
    measured, how = measured_rate(poured, out, grains, here)
    if here == threads:
        return measured, how
    scaled = measured / here * threads * PARALLEL_EFFICIENCY
    return scaled, (how + f"; x {threads}/{here} threads x {PARALLEL_EFFICIENCY} assumed parallel "
                          f"efficiency = {scaled:.3g} for a {threads}-thread job")


def measured_rate(poured, pulled, grains, threads):
    """(throughput, how) from the engine's pour and pull output: the pull's step rate, which is
    what `throughput` means (a bed's step is priced at cost.POUR_STEP_COST of it, measured on the
    ladder's pours); the pour's own ratio is printed beside it, not charged twice."""
    timing = re.search(r"timing: loop [\d.e+-]+ s for (\d+) steps, ([\d.e+-]+) particle-steps/s", pulled)
    pour = re.search(r"; ([\d.e+-]+) particle-steps/s", poured)
    if not timing or not pour:
        sys.exit(f"estimate_cost: could not read the throughput from:\n{poured}\n{pulled}")
    pull_rate, pour_rate = float(timing.group(2)), float(pour.group(1))
    how = (f"measured here: {pull_rate:.3g} particle-steps/s on {threads} thread(s), a pull of {timing.group(1)} "
           f"steps through a bed of {grains} grains; its pour ran at {pour_rate:.3g} ({pull_rate / pour_rate:.2g} "
           f"of a pull's step; beds are priced at {POUR_STEP_COST:g}, cost.POUR_STEP_COST)")
    return pull_rate, how


def wall_seconds(particle_steps, throughput, threads, cores):
    """(jobs at a time, wall seconds, whether a job gets fewer cores than its threads) of
    `particle_steps` on `cores` cores, for jobs of `threads` threads running at `throughput`
    particle-steps/s each. With fewer cores than threads a job runs at cores/threads of that
    rate: a throughput measured on a 16-thread node says nothing faster about a 2-core one."""
    if cores >= threads:
        parallel = cores // threads
        return parallel, particle_steps / throughput / parallel, False
    return 1, particle_steps / throughput * threads / cores, True


def _positive_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number of cores") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} cores: give at least 1")
    return value


def hours(seconds):
    h = seconds / 3600.0
    return f"{h:.3g} h" if h >= 1 else f"{seconds / 60.0:.3g} min"


def _use_measured_shares(path):
    """Price with the sleeping shares measured in the runs.csv at `path` (region_cost.measured_shares)."""
    import pandas as pd

    from . import region_cost

    try:
        shares = region_cost.measured_shares(pd.read_csv(path))
    except (OSError, ValueError, AttributeError, KeyError) as exc:
        sys.exit(f"estimate_cost: --asleep-from {path}: {exc} (give a study's runs.csv with pulls "
                 f"that had an active region, e.g. results/validate/active_region/runs.csv)")
    print(f"  sleeping share of the grains outside the region, measured in {path}: " + "; ".join(
        f"mu {mu:g}: " + ", ".join(f"Fr {fr:g}: {share:.3g}" for fr, share in points)
        for mu, points in shares.items()))
    region_cost.ASLEEP_SHARE = region_cost.ASLEEP_SHARE_DAMPED = shares   # whichever pour the beds had


def _recorded(check_dir, fit_dir, markdown=False, loo=False):
    """--check-recorded (--markdown, --leave-one-out) and --fit-recorded (granudrag_study.recorded)."""
    from . import recorded

    root = Path(check_dir or fit_dir)
    if not root.is_dir() or not recorded.recorded_rungs(root):
        sys.exit(f"estimate_cost: no recorded rung (<rung>/run.json) under {root}")
    if fit_dir:
        values, ratios = recorded.fit(root)
        print(f"fitted to {len(ratios)} rungs: " + ", ".join(f"{n} {v:.4g}" for n, v in zip(recorded.FITTED, values)))
        print(f"  measured / estimate {min(ratios.values()):.2f}-{max(ratios.values()):.2f}")
        if not check_dir:
            return 0
    rows = recorded.check(root)
    if markdown:
        recorded.print_markdown(rows, sys.stdout, recorded.leave_one_out(root) if loo else None)
    else:
        recorded.print_check(rows, sys.stdout)
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("config", nargs="?", help="study config (YAML)")
    ap.add_argument("--check-recorded", nargs="?", const=str(RECORDED), metavar="DIR",
                    help="print the estimate of every rung recorded in DIR (default: %(const)s) against its "
                         "measured CPU, at the throughput of the machine it ran on")
    ap.add_argument("--fit-recorded", nargs="?", const=str(RECORDED), metavar="DIR",
                    help="fit the CPU model's constants to the rungs recorded in DIR and print them (scipy; "
                         "about a minute)")
    ap.add_argument("--markdown", action="store_true",
                    help="with --check-recorded: a markdown table, with each rung's engine and the estimate "
                         "before the CPU model (particle-steps at the config's throughput)")
    ap.add_argument("--leave-one-out", action="store_true",
                    help="with --check-recorded --markdown: a column of each rung's ratio predicted by the "
                         "fit to the others (scipy; about a minute)")
    ap.add_argument("--throughput", type=float, help="particle-steps/s of one job (default: the config's)")
    ap.add_argument("--cores", type=_positive_int, default=len(os.sched_getaffinity(0)) or 1,
                    help="cores for the wall-time estimate (default: this machine's)")
    ap.add_argument("--by-sweep", action="store_true", help="break the cost down by sweep")
    ap.add_argument("--by-figure", action="store_true",
                    help="the cost of the runs behind each figure (the sweeps' `figures` keys)")
    ap.add_argument("--measure", action="store_true",
                    help="measure the throughput here: a pull through a bed poured here (under a minute)")
    ap.add_argument("--active_radius", type=float, metavar="R",
                    help="price the pulls as if every system's pull settings had active_radius R (d; "
                         "a system's own setting stays)")
    ap.add_argument("--active_diameters", type=float, metavar="K",
                    help="or: active_radius K D, in each pull's intruder diameters (3 agreed 7 d deep at "
                         "K_n = 2e4, 5 also deep and at 2e6, as config/faithful.yaml uses it; a "
                         "system's own setting stays)")
    ap.add_argument("--asleep-from", metavar="RUNS_CSV",
                    help="print the sleeping shares measured in a study's runs.csv (pulls with the "
                         "active region), the model's ASLEEP_SHARE, and price with them")
    ap.add_argument("--region-bound", action="store_true",
                    help="price every pull with the region as if each grain outside it slept from the "
                         "first step at no cost, frictionless beds too: the most any active region of "
                         "that radius can save (what is left is the pours and the region's inside)")
    ap.add_argument("--grains", type=int, help="grains of the --measure bed (default: smallest system's, <= 70000)")
    ap.add_argument("--binary", help="granudrag for --measure (default: the config's `granudrag`)")
    args = ap.parse_args(argv)
    if args.check_recorded or args.fit_recorded:
        return _recorded(args.check_recorded, args.fit_recorded, args.markdown, args.leave_one_out)
    if not args.config:
        ap.error("give a study config (or --check-recorded)")
    try:
        with open(args.config) as fh:
            config = yaml.safe_load(fh)
    except OSError as exc:
        sys.exit(f"estimate_cost: cannot read the config {args.config}: {exc.strerror}")
    except yaml.YAMLError as exc:
        sys.exit(f"estimate_cost: {args.config} is not valid YAML (quote a value that holds ': '): {exc}")
    if not isinstance(config, dict):
        sys.exit(f"estimate_cost: {args.config} is not a study config (a YAML mapping of keys such as "
                 f"systems and sweeps)")
    if args.active_radius is not None and args.active_diameters is not None:
        sys.exit("estimate_cost: give --active_radius (d) or --active_diameters (D), not both")
    for key, value in (("active_radius", args.active_radius), ("active_diameters", args.active_diameters)):
        if value is None:
            continue
        if value < 0:
            sys.exit(f"estimate_cost: --{key} {value}: give a radius >= 0")
        for sysc in (config.get("systems") or {}).values():
            own = (sysc.get("pull") or {}) if isinstance(sysc, dict) else {}
            if isinstance(sysc, dict) and not {"active_radius", "active_diameters"} & set(own):
                sysc["pull"] = {key: value, **own}
    if args.asleep_from and args.region_bound:
        sys.exit("estimate_cost: give --asleep-from (measured shares) or --region-bound (all asleep), not both")
    if args.asleep_from:
        _use_measured_shares(args.asleep_from)
    if args.region_bound:
        from . import region_cost

        region_cost.BOUND = True
    try:
        study.validate_config(config)
        config.setdefault("threads", 2)
        config.setdefault("throughput", 1.0e7)
        if args.throughput:
            config["throughput"] = args.throughput
        plan = study.plan(config)
    except study.ConfigError as exc:
        sys.exit(f"{args.config}: {exc}")
    how = "the config's `throughput`"
    # A config's rate for a job of more threads than measured here was scaled at the assumed
    # efficiency (faithful.yaml's, paper.yaml's); a rate given on the command line, or measured at
    # the job's own thread count, was not, and gets no range.
    assumed = not args.throughput
    if args.measure:
        binary = Path(args.binary) if args.binary else study.resolve_binary(config)
        grains = args.grains or min(70000, min(int(s["grains"]) for s in config["systems"].values()))
        config["throughput"], how = measure_throughput(binary, grains, int(config["threads"]))
        assumed = min(int(config["threads"]), os.cpu_count() or 1) < int(config["threads"])
        plan = study.plan(config)
    s = study.summary(plan)
    tp, threads = float(config["throughput"]), s["threads"]
    total = s["bed_work"] + s["pull_work"]
    bound = s["bed_work_bound"] + s["pull_work"]
    parallel, wall, squeezed = wall_seconds(total, tp, threads, args.cores)
    wall_bound = wall_seconds(bound, tp, threads, args.cores)[1]
    columns = f"{s['columns']} columns + " if s["columns"] else ""
    print(f"{args.config}: {columns}{s['beds']} beds + {s['pulls']} pulls = {s['columns'] + s['beds'] + s['pulls']} "
          f"simulation jobs (+ table, restitution, force trace, report)")
    if s["columns"]:
        print("  placed beds: each an intruder placed into its seed's column (granudrag place; columns poured "
              "once, counted with the beds; placement's settling time: workflow/granudrag_study/cost.py, PLACE_STOP)")
    print(f"  particle-steps: beds {s['bed_particle_steps']:.3g} expected (<= {s['bed_particle_steps_bound']:.3g}), "
          f"pulls {s['pull_particle_steps']:.3g}")
    print(f"  throughput {tp:.3g} particle-steps/s per job on {threads} thread(s) ({how})")
    print(f"  cost: {s['core_hours']:.3g} core-hours (beds {core_hours(s['bed_work'], config):.3g}, "
          f"pulls {core_hours(s['pull_work'], config):.3g}, of which their particle-steps "
          f"{core_hours(s['pull_particle_steps'], config):.3g}); at most {core_hours(bound, config):.3g} if "
          f"every pour runs to its max_settle_time (beds {core_hours(s['bed_work_bound'], config):.3g}; a bed's "
          f"particle-step costs {study.POUR_STEP_COST:g} of a pull's, cost.py POUR_STEP_COST)")
    if s["bed_particle_steps"] < s["bed_particle_steps_bound"]:
        print("  pours: undamped pours to 1e-6 and damped frictional ones are expected to stop at the "
              "kinetic-energy threshold early (measured settling times: workflow/granudrag_study/cost.py, "
              "UNDAMPED_SETTLE_PER_DENSITY, DAMPED_STOP)")
    packing = (f"each {threads}-thread job on {args.cores} cores, one at a time: the core-hours / {args.cores}"
               if squeezed else f"{parallel} job(s) at a time")
    print(f"  wall time on {args.cores} cores ({packing}): about {hours(wall)} (<= {hours(wall_bound)})")
    if s["pull_particle_steps"] < s["pull_particle_steps_whole"]:
        region = [p for p in plan.pulls.values() if study.expected_pull_cost(p, config) < study.pull_cost(p, config)]
        expected = "at most (--region-bound: all asleep outside R, at no cost)" if args.region_bound else "expected"
        print(f"  active region: {len(region)} of {s['pulls']} pulls sleep, {expected} to save "
              f"{1 - s['pull_particle_steps'] / s['pull_particle_steps_whole']:.0%} of the pulls' particle-steps "
              f"(whole cost {s['pull_particle_steps_whole']:.3g}; model and its measurements: "
              f"workflow/granudrag_study/region_cost.py; the scheduler's limits keep the whole cost)")
    if threads > MEASURED_THREADS and assumed:
        best, worst = (amdahl_efficiency(threads, share) for share in SERIAL_SHARE)
        print(f"  parallel efficiency: no rate here was measured beyond {MEASURED_THREADS} threads; a "
              f"{MEASURED_THREADS}-thread rate scaled to {threads} threads at the assumed {PARALLEL_EFFICIENCY} "
              f"(estimate.PARALLEL_EFFICIENCY; --measure does, and so did faithful.yaml's and paper.yaml's "
              f"throughput) prices {s['core_hours']:.3g} core-hours; Amdahl's law on the "
              f"{SERIAL_SHARE[0]:.0%}-{SERIAL_SHARE[1]:.1%} serial share measured at {MEASURED_THREADS} threads "
              f"(docs/engine.md) allows {worst:.2f}-{best:.2f}: "
              f"{s['core_hours'] * PARALLEL_EFFICIENCY / best:.3g}-"
              f"{s['core_hours'] * PARALLEL_EFFICIENCY / worst:.3g} core-hours, before memory bandwidth "
              f"and NUMA placement (not measured: run --measure on a node)")
    longest = max(plan.pulls.values(), key=lambda p: study.pull_work(p, config))
    print(f"  longest pull: {longest.key} "
          f"({hours(study.job_seconds(study.pull_work(longest, config), config))})")
    if args.by_sweep:
        cost = defaultdict(float)
        count = defaultdict(int)
        for p in plan.pulls.values():
            cost[p.sweep] += study.expected_pull_cost(p, config)
            count[p.sweep] += 1
        print("  pulls by sweep (particle-steps, share of all pulls):")
        for name, c in sorted(cost.items(), key=lambda kv: -kv[1]):
            print(f"    {name:24s} {count[name]:5d} pulls {c:10.3g} {c / s['pull_particle_steps']:6.1%}")
    if args.by_figure:
        print("  runs behind each figure (beds, pulls, core-hours with their beds; a run feeding "
              "several figures counts in each):")
        for figs, beds, pulls, ch, names in by_figure(config):
            label = ", ".join(f"Fig. {f}" if f[0].isdigit() else f for f in figs) or "(no figure named)"
            print(f"    {label}: {beds} beds, {pulls} pulls, {ch:.3g} core-h ({', '.join(names)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
