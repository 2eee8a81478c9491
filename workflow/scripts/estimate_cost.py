#!/usr/bin/python3
"""Job count and estimated cost of a study config, from measured throughput.

    /usr/bin/python3 workflow/scripts/estimate_cost.py config/paper.yaml [--throughput PS] [--cores N] [--by-sweep]

Cost model (workflow/scripts/study.py): a pull costs grains x travel / (V dt)
particle-steps, a pour at most grains x max_settle_time / dt (pours that reach
the kinetic-energy threshold stop earlier, so the bed figures are upper
bounds). dt is the config's, or granudrag's default (proportional to
K_n^-0.4). Core-hours = particle-steps / throughput x threads, where
throughput is the particle-steps per second of one job on `threads` threads
(the config's `throughput`, measured with `granudrag pull`, which prints it).
Wall time on N cores assumes N / threads jobs at a time, perfectly packed.
"""
import argparse
import sys
from collections import defaultdict
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
import study  # noqa: E402


def hours(seconds):
    h = seconds / 3600.0
    return f"{h:.3g} h" if h >= 1 else f"{seconds / 60.0:.3g} min"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("config", help="study config (YAML)")
    ap.add_argument("--throughput", type=float, help="particle-steps/s of one job (default: the config's)")
    ap.add_argument("--cores", type=int, default=2, help="cores for the wall-time estimate (default 2)")
    ap.add_argument("--by-sweep", action="store_true", help="break the cost down by sweep")
    args = ap.parse_args(argv)
    with open(args.config) as fh:
        config = yaml.safe_load(fh)
    schema = Path(__file__).resolve().parents[1] / "schemas" / "config.schema.yaml"
    try:
        study.validate_config(config, schema)
        config.setdefault("threads", 2)
        config.setdefault("throughput", 1.0e7)
        if args.throughput:
            config["throughput"] = args.throughput
        plan = study.plan(config)
    except study.ConfigError as exc:
        sys.exit(f"{args.config}: {exc}")
    s = study.summary(plan)
    tp, threads = float(config["throughput"]), s["threads"]
    total = s["bed_particle_steps"] + s["pull_particle_steps"]
    parallel = max(1, args.cores // threads)
    print(f"{args.config}: {s['beds']} beds + {s['pulls']} pulls = {s['beds'] + s['pulls']} "
          f"simulation jobs (+ table, restitution, force trace, report)")
    print(f"  particle-steps: beds <= {s['bed_particle_steps']:.3g}, pulls {s['pull_particle_steps']:.3g}")
    print(f"  throughput {tp:.3g} particle-steps/s per job on {threads} thread(s)")
    print(f"  cost: {s['core_hours']:.3g} core-hours "
          f"(beds <= {s['bed_particle_steps'] / tp * threads / 3600:.3g}, "
          f"pulls {s['pull_particle_steps'] / tp * threads / 3600:.3g})")
    print(f"  wall time on {args.cores} cores ({parallel} job(s) at a time): "
          f"<= {hours(total / tp / parallel)}")
    longest = max(plan.pulls.values(), key=lambda p: study.pull_cost(p, config))
    print(f"  longest pull: {longest.key} ({hours(study.job_seconds(study.pull_cost(longest, config), config))})")
    if args.by_sweep:
        cost = defaultdict(float)
        count = defaultdict(int)
        for p in plan.pulls.values():
            cost[p.sweep] += study.pull_cost(p, config)
            count[p.sweep] += 1
        print("  pulls by sweep (particle-steps, share of all pulls):")
        for name, c in sorted(cost.items(), key=lambda kv: -kv[1]):
            print(f"    {name:24s} {count[name]:5d} pulls {c:10.3g} {c / s['pull_particle_steps']:6.1%}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
