"""Estimated cost of the study's jobs (particle-steps, wall time) and their scheduler resources.

A pull costs grains x travel / (V dt) particle-steps, a pour at most grains x max_settle_time
/ dt; dt is the config's, or granudrag's default (analysis.physics.default_dt). The wall time
of a job is its particle-steps over the config's `throughput` (particle-steps per second of
one job on `threads` threads).
"""

import math

from ..physics import default_dt


def bed_dt(bed, config):
    dt = (config["systems"][bed.system].get("pour") or {}).get("dt")
    return float(dt) if dt else default_dt(bed.value("kn"))


def bed_cost(bed, config):
    """Upper bound of a pour's particle-steps: every grain for the whole settling time."""
    sysc = config["systems"][bed.system]
    t = float((sysc.get("pour") or {}).get("max_settle_time", 100.0))
    return int(sysc["grains"]) * t / bed_dt(bed, config)


def pull_distance(pull, config):
    sysc = config["systems"][pull.bed.system]
    settings = dict(sysc.get("pull") or {})
    settings.update(dict(pull.settings))
    distance = float(settings.get("distance", 0.0) or 0.0)
    return distance if distance > 0 else float(sysc["lx"])


def pull_cost(pull, config):
    """Particle-steps of a pull: grains x travel / (V dt)."""
    grains = int(config["systems"][pull.bed.system]["grains"])
    return grains * pull_distance(pull, config) / (pull.V * bed_dt(pull.bed, config))


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
    """Numbers of jobs and estimated particle-steps and core-hours."""
    config = plan_.config
    bed_ps = sum(bed_cost(b, config) for b in plan_.beds.values())
    pull_ps = sum(pull_cost(p, config) for p in plan_.pulls.values())
    threads = int(config["threads"])
    core_h = (bed_ps + pull_ps) / float(config["throughput"]) * threads / 3600.0
    return {
        "beds": len(plan_.beds),
        "pulls": len(plan_.pulls),
        "bed_particle_steps": bed_ps,
        "pull_particle_steps": pull_ps,
        "core_hours": core_h,
        "threads": threads,
    }
