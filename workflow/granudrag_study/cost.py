"""Estimated cost of the study's jobs (particle-steps, wall time) and their scheduler resources.

A pull costs grains x travel / (V dt) particle-steps, a pour at most grains x max_settle_time
/ dt; dt is the config's, or granudrag's default (analysis.physics.default_dt). The wall time
of a job is its particle-steps over the config's `throughput` (particle-steps per second of
one job on `threads` threads).
"""

import math

from analysis.physics import default_dt, froude

from .region_cost import SLEEPING_COST, asleep_fraction

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
    dt = (config["systems"][bed.system].get("pour") or {}).get("dt")
    return float(dt) if dt else default_dt(bed.value("kn"))


def bed_cost(bed, config):
    """Upper bound of a pour's particle-steps: every grain for the whole settling time."""
    sysc = config["systems"][bed.system]
    t = float((sysc.get("pour") or {}).get("max_settle_time", 100.0))
    return int(sysc["grains"]) * t / bed_dt(bed, config)


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
    return grains * pull_distance(pull, config) / (pull.V * bed_dt(pull.bed, config))


def expected_pull_cost(pull, config):
    """Particle-steps a pull is expected to cost: pull_cost less what the active region saves
    (region_cost), the cost of a study's estimate; the scheduler's limits take pull_cost."""
    asleep = asleep_fraction(pull, config, pull_distance(pull, config))
    return pull_cost(pull, config) * (1.0 - (1.0 - SLEEPING_COST) * asleep)


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
    worst = max(job_seconds(bed_cost(b, config), config) for b in plan_.beds.values()) / 60.0
    return max(1, job_attempts(1.5 * worst + 5, config) - 1)


def summary(plan_):
    """Numbers of jobs and estimated particle-steps and core-hours (the pulls' expected cost; their
    whole cost, without the active region's saving, as pull_particle_steps_whole)."""
    config = plan_.config
    bed_ps = sum(bed_cost(b, config) for b in plan_.beds.values())
    pull_ps = sum(expected_pull_cost(p, config) for p in plan_.pulls.values())
    whole = sum(pull_cost(p, config) for p in plan_.pulls.values())
    threads = int(config["threads"])
    core_h = (bed_ps + pull_ps) / float(config["throughput"]) * threads / 3600.0
    return {
        "beds": len(plan_.beds),
        "pulls": len(plan_.pulls),
        "bed_particle_steps": bed_ps,
        "pull_particle_steps": pull_ps,
        "pull_particle_steps_whole": whole,
        "core_hours": core_h,
        "threads": threads,
    }
