"""Command lines of the study's jobs: `granudrag pour` for a bed (or a placed system's column),
`granudrag place` for a placed bed, `granudrag pull` for a pull."""

import math

from .config import placement_settings, pour_settings, settle_limit
from .cost import bed_cost, job_seconds, pull_cost, pull_distance
from .paths import Pull, fmt, parse_speed


def _flags(settings):
    out = []
    for k, v in settings.items():
        if v is None:
            continue
        if isinstance(v, bool):
            if v:
                out.append(f"--{k}")
            continue
        out += [f"--{k}", fmt(v) if isinstance(v, float) else str(v)]
    return out


def pour_args(bed, config):
    """granudrag pour arguments (without --output and --threads) for a bed."""
    return _pour_args(bed, config, ["--intruder_diameter", bed.D,
                                    "--depth" if bed.place == "h" else "--intruder_z", bed.pos])


def column_args(bed, config):
    """granudrag pour arguments (without --output and --threads) of the column a placed bed's
    intruder goes into: the bed's system, contact law and seed, no intruder (so no depth)."""
    return _pour_args(bed, config, ["--intruder_diameter", "0"])


def _pour_args(bed, config, intruder):
    """A pour's arguments for bed's system and contact law, with `intruder`'s in their place."""
    sysc = config["systems"][bed.system]
    args = ["--lx", fmt(sysc["lx"]), "--ly", fmt(sysc["ly"]), "--grains", str(int(sysc["grains"]))]
    args += intruder + ["--mu", bed.mu, "--kn", bed.kn, "--gamman", bed.gn, "--seed", bed.seed]
    settings = pour_settings(config, bed.system)
    if not settings.get("checkpoint_interval"):
        interval = pour_checkpoint_interval(bed, config)
        if interval:
            settings["checkpoint_interval"] = interval
    return args + _flags(settings)


def place_args(bed, config):
    """granudrag place arguments (without --bed, --output and --threads) of a placed bed: its D
    and depth, and its system's `placement` settings."""
    args = ["--intruder_diameter", bed.D, "--depth", bed.pos]
    return args + _flags(placement_settings(config, bed.system))


def pour_checkpoint_interval(bed, config):
    """Simulated time between a pour's checkpoints when its settling may take longer than
    `checkpoint_minutes` of estimated wall time (or a quarter of max_runtime), else None: no
    checkpoints, and the bed is the same as one poured without them. Simulated time, as for
    pulls: a pour resumed over several jobs gives the bed an uninterrupted pour gives."""
    minutes = job_seconds(bed_cost(bed, config), config) / 60.0
    gap = float(config.get("checkpoint_minutes", 60))
    if config.get("max_runtime"):
        gap = min(gap, int(config["max_runtime"]) / 4.0)  # several checkpoints per job
    pieces = math.ceil(minutes / gap)
    if pieces <= 1:
        return None
    return float(f"{settle_limit(config, bed.system) / pieces:.4g}")


def pull_args(bed, speed, plan_):
    """granudrag pull arguments (without --bed, --output, --threads) for a pull."""
    kind, value = parse_speed(speed)
    sysc = plan_.config["systems"][bed.system]
    settings = dict(sysc.get("pull") or {})
    settings.update(plan_.pull_settings(bed.key, speed))
    args = ["--froude" if kind == "Fr" else "--speed", fmt(value)]
    if not settings.get("checkpoint_interval"):
        interval = checkpoint_interval(Pull(bed, speed, tuple(settings.items())), plan_.config)
        if interval:
            settings["checkpoint_interval"] = interval
    return args + _flags(settings)


def checkpoint_interval(pull, config):
    """Simulated time between checkpoints when a tenth of the pull would take longer than
    `checkpoint_minutes` of estimated wall time (else None: granudrag's tenth). Simulated,
    not wall, time: the checkpoints then fall on the same steps in every run, so a resumed
    pull stays bitwise identical to an uninterrupted one."""
    minutes = job_seconds(pull_cost(pull, config), config) / 60.0
    gap = float(config.get("checkpoint_minutes", 60))
    if config.get("max_runtime"):
        gap = min(gap, int(config["max_runtime"]) / 4.0)  # several checkpoints per job
    pieces = math.ceil(minutes / gap)
    if pieces <= 10:
        return None
    return float(f"{pull_distance(pull, config) / pull.V / pieces:.4g}")


def movie_pull_args(pull, config):
    """granudrag pull arguments (without --bed, --output, --threads) of the movie (workflow
    target `movie`): `pull` again with `movie.frames` frames over its travel (--dump_interval)
    and no sequential stopping, so the movie shows the whole travel."""
    frames = int((config.get("movie") or {}).get("frames", 120))
    settings = pull.settings_in(config)
    settings.pop("target_error", None)
    settings.pop("min_distance", None)
    movie = Pull(pull.bed, pull.speed, tuple(settings.items()))
    distance = pull_distance(movie, config)
    kind, value = parse_speed(pull.speed)
    args = ["--froude" if kind == "Fr" else "--speed", fmt(value)] + _flags(settings)
    return args + ["--dump_interval", f"{distance / pull.V / (frames - 1):.6g}"]
