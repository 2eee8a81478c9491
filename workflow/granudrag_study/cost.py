"""Estimated cost of the study's jobs (particle-steps, wall time) and their scheduler resources.

A pull costs grains x travel / (V dt) particle-steps, a pour at most grains x max_settle_time
/ dt and is expected to cost grains x its expected settling time / dt; a placed system's bed
is a placement (granudrag place) into a column poured once per seed: the column costs a pour,
the placement at most grains x its max_settle_time / dt, expected grains x its expected
settling time (PLACE_STOP) / dt; dt is the config's, or
granudrag's default (analysis.core.physics.default_dt), and a pull's the collision time over its
`collision_steps` when it sets them. The wall time of a job is its
particle-steps over the config's `throughput` (particle-steps per second of one job on
`threads` threads).

What a job costs in CPU is more than its particle-steps: a pull also pays per grain for its start
and end (the bed read, lists built, checkpoints and snapshots written) and per unit of simulated
time (its samples), which weigh most in short pulls and slow ones (the CPU model below, fitted to
the reproduction ladder's recorded rungs: granudrag_study.recorded). The study's estimate
(summary) prices that work, in particle-step equivalents, at the config's throughput, which is
then the rate of a pull's steps on the machine; the scheduler's limits keep the particle-steps.
"""

import math

from analysis.core.physics import collision_time, default_dt, froude

from .config import (
    PLACE_MIN_SETTLE_TIME_DEFAULT,
    SETTLE_DAMPING_DEFAULT,
    place_limit,
    placed,
    placement_settings,
    pour_settings,
    settle_limit,
)
from .region_cost import asleep_fraction, overhead, sleeping_cost

# Sequential stopping (a pull's `target_error`): the drag's relative standard error after L d of
# travel past the transient is about c(Fr) / sqrt(L), and the stopping rule wants at least
# STOP_MIN_DOF effective samples, one per STOP_CORRELATION_LENGTH of travel. Measured on the
# pulls of config/ladder/crossover-k2e5-box12.yaml (52 pulls of 12 d, K_n = 2e5, D = 2 and 3, h = 14 d) and of
# a shallower variant (78 pulls, h = 6.5 d): the median of drag_err / drag * sqrt(L) is
# 0.12-0.15 at Fr <= 1, 0.29-0.32 at Fr 1-3, 0.42-0.51 at Fr 3-6, 0.71-0.93 at Fr 6-15, and
# of L / drag_dof 1.0-2.7 d; the line below runs between those medians.
STOP_ERROR_INTERCEPT, STOP_ERROR_SLOPE = 0.10, 0.075
STOP_CORRELATION_LENGTH = 2.5  # d
STOP_MIN_DOF = 10              # as granudrag pull's stopping rule


def expected_stop_distance(Fr, target, transient, min_distance, most):
    """Expected travel, d, of a pull with a target error: the transient, then the travel the
    error model needs, no less than min_distance, at most `most` (the pull's distance)."""
    c = STOP_ERROR_INTERCEPT + STOP_ERROR_SLOPE * Fr
    needed = max((c / target) ** 2, STOP_MIN_DOF * STOP_CORRELATION_LENGTH)
    return min(most, max(min_distance, transient + needed))


def bed_dt(bed, config):
    dt = pour_settings(config, bed.system).get("dt")
    return float(dt) if dt else default_dt(bed.value("kn"))


def pull_dt(pull, config):
    """The pull's step: its bed's, or the collision time over the pull's collision_steps."""
    steps = pull.settings_in(config).get("collision_steps")
    return collision_time(pull.bed.value("kn")) / float(steps) if steps else bed_dt(pull.bed, config)


def column_cost(bed, config):
    """Upper bound of a pour's particle-steps (a bed's, or a placed bed's column's): every grain
    for the whole settling time."""
    grains = int(config["systems"][bed.system]["grains"])
    return grains * settle_limit(config, bed.system) / bed_dt(bed, config)


def bed_cost(bed, config):
    """Upper bound of a bed's particle-steps: its pour's (column_cost), or a placed bed's
    placement's, every grain for the placement's max_settle_time."""
    if not placed(config, bed.system):
        return column_cost(bed, config)
    grains = int(config["systems"][bed.system]["grains"])
    return grains * place_limit(config, bed.system) / bed_dt(bed, config)


# When a pour stops: when the grains' kinetic energy falls below ke_threshold, else at
# max_settle_time. Undamped pours to a ke_threshold of at least UNDAMPED_STOP_THRESHOLD (every
# rung of the reproduction ladder) stop after UNDAMPED_SETTLE_PER_DENSITY time units per grain per
# d^2 of base (the column's height), measured at 43.6-43.75 grains per d^2 (K_n = 2e6, mu = 0.5,
# 1e-6): 26.0 and 29.5 (crossover-k2e6-box40-deep's 70,000-grain pours: 390,988 and 443,621 of
# their 601,520 steps, results/reproduction/crossover-k2e6-box40-deep/README.md) and 30
# (crossover-k2e6-box20-deep; its other pour ran to 40, results/reproduction/history.md): 28.5 on
# average. Proportional to the height is an assumption; fitted freely to the ladder's recorded CPU
# (granudrag_study.recorded) it comes out 1.10, but the totals hardly constrain it (the pours are
# 10-25 % of each rung). Undamped pours to lower thresholds run to max_settle_time (below).
UNDAMPED_SETTLE_PER_DENSITY = 0.65
UNDAMPED_STOP_THRESHOLD = 1e-6
# Measured with settle_damping 1 (docs/study-outcomes.md, "Damped pours"), in
# 10 d x 10 d columns as deep as faithful.yaml's systems (K_n = 2e5, ke_threshold 1e-7): at system
# I's depth (43.75 grains per d^2) mu = 0.1 stops after 37.0 time units, 0.25 after 25.5, 0.5
# after 26.5 (the validation studies' shallower 40 d beds, 16 grains per d^2, 1e-6, mu = 0.25-0.8:
# 24.0-28.0 over 15 beds; 28, the slowest, is taken from mu = 0.25 on); at system II's (93.75 per
# d^2) mu = 0.1 after 42.0, 0.5 after 40.0. Linear in mu at each depth, then in depth, held beyond
# the measured points. Frictionless beds creep in bursts, damped or not (mu = 0, system I's depth:
# 1.2e-7 per grain at 100), and undamped beds breathe (system I, mu = 0.5: at 40 of 40): both run
# to max_settle_time, as do frictions below 0.1, other dampings and lower thresholds (not measured).
DAMPED_STOP = (                                   # (grains per d^2, ((mu, settling time), ...))
    (43.75, ((0.1, 37.0), (0.25, 28.0))),
    (93.75, ((0.1, 42.0), (0.5, 40.0))),
)
DAMPED_STOP_MEASURED = {"settle_damping": 1.0, "ke_threshold": 1e-7}
# DAMPED_STOP's times are at K_n = 2e5; a softer bed settles longer: the 10 damped pours of
# config/ladder/scaling-k2e4-deep.yaml (K_n = 2e4, 93.75 grains per d^2, mu = 0.5, settle_damping 1,
# 1e-7; their beds' settle_time, 2026-12-03/04) stopped after 45.5-53.5, 48.6 on average, against
# DAMPED_STOP's 40.0 there: DAMPED_SOFT_FACTOR at K_n <= DAMPED_SOFT_KN, linear in log K_n up to
# 1 at 2e5, 1 above (stiffer beds not measured damped).
DAMPED_SOFT_KN, DAMPED_SOFT_FACTOR = 2e4, 48.6 / 40.0


def _between(points, x):
    """Linear interpolation between two (x, y) points, held at the ends' y beyond them."""
    (x0, y0), (x1, y1) = points
    return y0 + (min(max(x, x0), x1) - x0) * (y1 - y0) / (x1 - x0)


def expected_settle_time(bed, config):
    """Simulated time a pour is expected to run (UNDAMPED_SETTLE_PER_DENSITY, DAMPED_STOP), at most
    its max_settle_time."""
    sysc = config["systems"][bed.system]
    pour, limit = pour_settings(config, bed.system), settle_limit(config, bed.system)
    damping = float(pour.get("settle_damping", SETTLE_DAMPING_DEFAULT) or 0.0)
    damped = damping == DAMPED_STOP_MEASURED["settle_damping"]
    threshold = float(pour.get("ke_threshold", 0.0) or 0.0)
    mu = bed.value("mu")
    density = int(sysc["grains"]) / (float(sysc["lx"]) * float(sysc["ly"]))
    if damping == 0 and threshold >= UNDAMPED_STOP_THRESHOLD:
        return min(limit, UNDAMPED_SETTLE_PER_DENSITY * density)
    if not damped or threshold < DAMPED_STOP_MEASURED["ke_threshold"] or mu < DAMPED_STOP[0][1][0][0]:
        return limit
    at_depths = [(n, _between(points, mu)) for n, points in DAMPED_STOP]
    softer = _between(((math.log10(DAMPED_SOFT_KN), DAMPED_SOFT_FACTOR), (math.log10(2e5), 1.0)),
                      math.log10(float(bed.value("kn"))))
    return min(limit, softer * _between(at_depths, density))


def expected_column_cost(bed, config):
    """Particle-steps a pour (a bed's, or a placed bed's column's) is expected to cost:
    column_cost for its expected settling time."""
    sysc = config["systems"][bed.system]
    return int(sysc["grains"]) * expected_settle_time(bed, config) / bed_dt(bed, config)


# When a placement stops (granudrag place: the intruder held, the bed settling again to its
# ke_threshold, by default the column's, after at least min_settle_time). Measured on one thread,
# K_n = 2e4, mu = 0.5: in an 8 d x 8 d column of 700 grains (undamped, to 1e-5) D = 2 at h = 3
# settled at t = 9.0; in 20 d x 20 d columns of 6,400 grains (13.5 d deep), undamped to 1e-5 (the
# column poured to 1e-5, t = 21.0) D = 2 at h = 3 at 4.5 (18 grains removed, 37.5 s wall), D = 4 at
# h = 8 at 6.0 (83 removed, 47.6 s), damped (settle_damping 1) D = 2 at h = 3 at 3.0; damped to 1e-7
# (the column poured damped to 1e-7, t = 28.5) D = 2 at h = 3 at 6.0 (17 removed, 47.2 s; to 1e-6:
# 3.5) and D = 4 at h = 8 at 16.0 (77 removed, 93.7 s). Undamped to 1e-7, D = 2 at h = 3 ran to
# max_settle_time 20 (3.5e-7 per grain at t = 20): an undamped placement below 1e-5 runs to its
# max_settle_time, as does any below 1e-7 (not measured). Each entry: (lowest ke_threshold, damped
# placements only, the slowest settling time measured at or above it).
PLACE_STOP = ((1e-5, False, 9.0), (1e-7, True, 16.0))


def _place_threshold(bed, config):
    """The ke_threshold a placement settles to: its own, or its column's pour's (granudrag's)."""
    own = placement_settings(config, bed.system).get("ke_threshold")
    return float(own if own else pour_settings(config, bed.system).get("ke_threshold", 1e-7))


def expected_place_time(bed, config):
    """Simulated time a placement is expected to settle (PLACE_STOP), at least its
    min_settle_time, at most its max_settle_time."""
    settings = placement_settings(config, bed.system)
    limit = place_limit(config, bed.system)
    least = float(settings.get("min_settle_time", PLACE_MIN_SETTLE_TIME_DEFAULT) or 0.0)
    damped = float(settings.get("settle_damping", SETTLE_DAMPING_DEFAULT) or 0.0) > 0
    threshold = _place_threshold(bed, config)
    for lowest, needs_damping, time in PLACE_STOP:
        if threshold >= lowest and (damped or not needs_damping):
            return min(limit, max(least, time))
    return limit


# What a bed's (a pour's, a column's, a placement's) particle-step costs, in a pull's: its grains
# fall and rearrange, the neighbour lists rebuilt far more often than in a pull's bed at rest. From
# the per-job benchmarks of the two rungs recorded in pieces (results/reproduction/<rung>/pieces/
# benchmarks/), each priced at the rate its own pulls of over a minute ran at under the CPU model
# below (2026-12-04): the 3 undamped pours of crossover-k2e6-box40-deep (70,000 grains, K_n = 2e6,
# settled at 26-30 as priced; beside other work) cost 2.08-2.44 of a pull's step, 2.25 on average;
# the 10 damped pours of scaling-k2e4-deep (84,375 grains, K_n = 2e4, their measured settling time,
# DAMPED_SOFT_FACTOR) 1.63-2.40, 2.11 on average. The recorded rungs' totals hardly constrain it
# (pours are 8-32 % of each rung's particle-steps: a factor 1 to 2 fits them alike, within
# 0.89-1.16, the machines' rates moving).
POUR_STEP_COST = 2.1


def expected_bed_cost(bed, config):
    """Particle-steps a bed is expected to cost: a pour's for its expected settling time, or a
    placed bed's placement's (its column is priced once per seed, expected_column_cost): the
    cost of a study's estimate; the scheduler's limits take bed_cost."""
    if not placed(config, bed.system):
        return expected_column_cost(bed, config)
    grains = int(config["systems"][bed.system]["grains"])
    return grains * expected_place_time(bed, config) / bed_dt(bed, config)


def pull_distance(pull, config):
    """Travel of a pull, d: its distance (0: the box length), or with a target error the
    expected stopping distance (expected_stop_distance)."""
    sysc = config["systems"][pull.bed.system]
    settings = pull.settings_in(config)
    distance = float(settings.get("distance", 0.0) or 0.0)
    most = distance if distance > 0 else float(sysc["lx"])
    target = float(settings.get("target_error", 0.0) or 0.0)
    if target <= 0:
        return most
    D = pull.bed.value("D")
    transient = float(settings.get("transient", -1.0))
    transient = transient if transient >= 0 else min(D + 1.0, most / 4)
    return expected_stop_distance(float(froude(pull.V, D)), target, transient,
                                  float(settings.get("min_distance", 0.0) or 0.0), most)


def pull_cost(pull, config):
    """Particle-steps of a pull: grains x travel / (V dt)."""
    grains = int(config["systems"][pull.bed.system]["grains"])
    return grains * pull_distance(pull, config) / (pull.V * pull_dt(pull, config))


def region_factor(pull, config):
    """What the active region leaves of a pull's per-step work (region_cost): 1 without it; less
    the share of grains asleep, each still costing sleeping_cost, plus the region's overhead."""
    asleep = asleep_fraction(pull, config, pull_distance(pull, config))
    return 1.0 + overhead(pull, config) - (1.0 - sleeping_cost(pull, config)) * asleep


def expected_pull_cost(pull, config):
    """Particle-steps a pull is expected to cost: pull_cost less what the active region saves
    (region_factor), the cost of a study's estimate; the scheduler's limits take pull_cost."""
    return pull_cost(pull, config) * region_factor(pull, config)


# The CPU model: a pull costs, besides its particle-steps, PULL_START_STEPS particle-step
# equivalents per grain (reading the bed, building the lists, ten checkpoints and the snapshots
# written, the run file's end) and PULL_TIME_STEPS per grain per unit of simulated time (a sample
# every sample_interval; the lists rebuilt as the bed moves), at the rate of its steps; a pour's
# step costs POUR_STEP_COST of a pull's (above). Fitted, with the three machines' rates
# (LADDER_MACHINES), to the CPU seconds of the reproduction ladder's 16 recorded rungs
# (results/reproduction/*/run.json: 5 parameters, 16 data) by `/usr/bin/python3
# workflow/scripts/estimate_cost.py --fit-recorded` (granudrag_study.recorded; 2026-12-04, with
# POUR_STEP_COST 2.1; 2026-12-02's fit, pours at a pull's step and 2 machines: 12,170 and 1,037).
# Alone, at the configs' throughput, particle-steps priced the 12 d boxes 1.3-3x too high and the
# 30-40 d boxes 1.2-1.6x too low: mostly the machines; the rungs' totals constrain these two
# constants loosely (their fitted values moved 30-80 % with POUR_STEP_COST, the ratios 1 %).
PULL_START_STEPS = 8793.0
PULL_TIME_STEPS = 1847.0

# The machines the recorded rungs ran on (run.json's machine.cpu and start): the throughput (a
# pull's step rate, particle-steps per second of one 1-thread job) of each, the last entry whose CPU
# name is in the record's and whose date is on or before its start. The first two were 2-core
# virtual machines reporting "Intel(R) Xeon(R) Processor"; the second, from 2026-11-29 (2 MiB L2,
# 260 MiB L3), runs 1.5x slower per core in the fit, as docs/log/benchmark.md found on the 7.7k
# bench's loop (86-119 ns per particle-step there against 65 on the first); the third reported
# "AMD EPYC" (crossover-k2e6-box40-deep, the only rung on it: its rate is that rung's own). Fitted as
# above. The fourth, from 2026-12-03, an "AMD EPYC" host again, ran 70 of scaling-k2e4-deep's 84
# jobs (the other 14 on an Intel host on 2026-12-04: the rung's run.json names the majority): its
# rate is that of the rung's 50 pulls of over a minute (their work over their CPU plus the
# benchmark's 15 s), not fitted to the rung's total (0.72 of it at the second machine's rate).
# The fifth, from 2026-12-04, an "Intel(R) Xeon(R) Processor" host again but 1.4x the second's
# rate: it ran phi-k2e4-box30-deep's 36 jobs, whose 18 pulls give 2.26e7 as the fourth's gave
# its rate (their beds, priced by the same model, 2.51e7); at the second's rate the rung came out
# at 0.68.
LADDER_MACHINES = (
    ("Intel", "2026-11-25", 2.439e7),
    ("Intel", "2026-11-29", 1.637e7),
    ("AMD EPYC", "2026-11-25", 1.310e7),
    ("AMD EPYC", "2026-12-03", 2.21e7),
    ("Intel", "2026-12-04", 2.26e7),
)


def bed_work(bed, config):
    """Pull-step equivalents of a bed job's CPU: its expected particle-steps (expected_bed_cost)
    at POUR_STEP_COST."""
    return POUR_STEP_COST * expected_bed_cost(bed, config)


def column_work(bed, config):
    """Pull-step equivalents of a placed bed's column's pour: expected_column_cost at POUR_STEP_COST."""
    return POUR_STEP_COST * expected_column_cost(bed, config)


def pull_time(pull, config):
    """Simulated time of a pull, sqrt(d/g): its expected travel over V."""
    return pull_distance(pull, config) / pull.V


def pull_work(pull, config):
    """Particle-step equivalents of a pull's CPU (the CPU model): its expected particle-steps and
    its grains' start and sampling. The active region discounts the time term as it does the
    steps: the term's work is per grain and step as theirs is (the fit cannot tell them apart at
    one K_n), and bench/region_map.sh measured the region's saving on the whole CPU (2.69x in the
    40 d box's yield pull, where the undiscounted term would have capped it at 1.5x)."""
    grains = int(config["systems"][pull.bed.system]["grains"])
    region = region_factor(pull, config)
    overhead = grains * (PULL_START_STEPS + PULL_TIME_STEPS * pull_time(pull, config) * region)
    return pull_cost(pull, config) * region + overhead


def job_seconds(particle_steps, config):
    """Estimated wall time of one job on config['threads'] threads."""
    return particle_steps / float(config["throughput"])


def job_attempts(minutes, config):
    """Jobs needed for a run of `minutes` estimated wall time under max_runtime: its time
    limit doubles per retry up to the cap, and each retry resumes from the checkpoint."""
    cap = config.get("max_runtime")
    if not cap:
        return 1
    limit, done, attempts = minutes, 0.0, 0
    while done < minutes:
        attempts += 1
        done += min(limit * 2 ** (attempts - 1), cap) * 0.75  # a quarter lost to restarts
    return attempts


def job_resources(cost, grains, config, attempt=1):
    """(mem_mb, runtime in minutes) for a job: a generous bound for schedulers, doubled on
    each retry (a time limit is the likely reason; the retry resumes from the checkpoint),
    at most max_runtime."""
    mem = int(200 + 0.004 * grains)  # ~1.5 kB per grain measured; x2.5 margin
    minutes = (int(math.ceil(3.0 * job_seconds(cost, config) / 60.0)) + 5) * 2 ** (attempt - 1)
    if config.get("max_runtime"):
        minutes = min(minutes, int(config["max_runtime"]))
    return mem, minutes


def pull_retries(plan_):
    """Retries of the pull rule: None (the profile's restart-times) without max_runtime,
    else enough for the longest pull to finish in pieces."""
    config = plan_.config
    if not config.get("max_runtime") or not plan_.pulls:
        return None
    worst = max(job_seconds(pull_cost(p, config), config) for p in plan_.pulls.values()) / 60.0
    # 1.5 x the estimate: the throughput is measured, the 3x of job_resources is for one job.
    return max(1, job_attempts(1.5 * worst + 5, config) - 1)


def bed_retries(plan_):
    """Retries of the bed rule, as pull_retries: None without max_runtime, else enough for
    the longest pour (its max_settle_time) to finish in pieces, each resuming from the last
    checkpoint."""
    config = plan_.config
    if not config.get("max_runtime") or not plan_.beds:
        return None
    costs = [bed_cost(b, config) for b in plan_.beds.values()]
    costs += [column_cost(b, config) for b in plan_.columns.values()]
    worst = max(job_seconds(c, config) for c in costs) / 60.0
    return max(1, job_attempts(1.5 * worst + 5, config) - 1)


def summary(plan_):
    """Numbers of jobs and estimated particle-steps and core-hours: the expected cost of the beds
    (placed beds' columns included) and pulls, the core-hours of the beds' and pulls' work (bed_work
    at POUR_STEP_COST, pull_work: the CPU model) rather than their particle-steps; the beds' upper
    bound (every pour and placement to its max_settle_time) as bed_particle_steps_bound (bed_work_bound
    at POUR_STEP_COST), the pulls' whole cost (without the active region's saving) as
    pull_particle_steps_whole."""
    config = plan_.config
    bed_ps = sum(expected_bed_cost(b, config) for b in plan_.beds.values())
    bound = sum(bed_cost(b, config) for b in plan_.beds.values())
    bed_ps += sum(expected_column_cost(b, config) for b in plan_.columns.values())
    bound += sum(column_cost(b, config) for b in plan_.columns.values())
    pull_ps = sum(expected_pull_cost(p, config) for p in plan_.pulls.values())
    work = sum(pull_work(p, config) for p in plan_.pulls.values())
    whole = sum(pull_cost(p, config) for p in plan_.pulls.values())
    threads = int(config["threads"])
    core_h = (POUR_STEP_COST * bed_ps + work) / float(config["throughput"]) * threads / 3600.0
    return {
        "beds": len(plan_.beds),
        "columns": len(plan_.columns),
        "pulls": len(plan_.pulls),
        "bed_particle_steps": bed_ps,
        "bed_particle_steps_bound": bound,
        "bed_work": POUR_STEP_COST * bed_ps,
        "bed_work_bound": POUR_STEP_COST * bound,
        "pull_particle_steps": pull_ps,
        "pull_particle_steps_whole": whole,
        "pull_work": work,
        "core_hours": core_h,
        "threads": threads,
    }
