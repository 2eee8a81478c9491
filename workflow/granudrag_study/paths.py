"""Names of the study's jobs: a bed and a pull as paths whose numbers are their parameters.

A bed is identified by its system (box, grain count, pour settings), the intruder diameter
D, its placement (depth h below the free surface, or height z above the wall), friction mu,
K_n, gamma_n and the pour's seed; its path (`bed_file`) names all but the system's settings.
A system whose beds are placed (`placement:`) pours one column per seed, without an intruder,
and places each bed's intruder into it (granudrag place); the column's path (`column_file`) is
the bed's without D and depth. A pull is a bed and a speed, given as a Froude number or a speed
(`run_file`). The components of these paths, their order and the table column each fills are
declared once, with examples, in analysis.core.path_scheme (which the run reader parses by too);
Bed's fields are that declaration's.

Numbers in paths are written by `fmt` and the jobs use exactly the numbers the path states,
so a path is a complete, reproducible name.
"""

import math
from dataclasses import dataclass, field

from analysis.core import path_scheme as scheme
from analysis.core.physics import froude_speed

from .config import ConfigError

# Wildcard patterns (regexes without groups) of one bed, one speed and one column in a path,
# from the one declaration of the path's components (analysis.core.path_scheme).
BED_PATTERN = scheme.pattern(scheme.BED)
SPEED_PATTERN = scheme.pattern((scheme.SPEED,))
COLUMN_PATTERN = scheme.pattern(scheme.COLUMN)


def fmt(x):
    """Compact, exact-enough text of a number for paths: 2, 0.5, 2e4, 199.054."""
    x = float(x)
    if not math.isfinite(x):
        raise ConfigError(f"not a finite number: {x}")
    if x == 0:
        return "0"
    if abs(x) >= 1e4 or abs(x) < 1e-3:
        mant, exp = f"{x:.7e}".split("e")
        mant = mant.rstrip("0").rstrip(".")
        return f"{mant}e{int(exp)}"
    return f"{x:.8g}"


def number(text, what="number"):
    try:
        return float(text)
    except (TypeError, ValueError):
        raise ConfigError(f"{what}: '{text}' is not a number") from None


def parse_speed(text):
    m = scheme.parse((scheme.SPEED,), text)
    if not m:
        expected = " or ".join(scheme.part(name, "<number>") for name in scheme.SPEED.names)
        raise ConfigError(f"not a speed: '{text}' (expected {expected})")
    return m["kind"], number(m["value"], f"speed {text}")


def speed_key(kind, value):
    """A pull's speed as its path names it: speed_key("Fr", 1.5) is "Fr~1.5"."""
    return scheme.key((scheme.SPEED,), {"kind": kind, "value": fmt(value)})


@dataclass(frozen=True)
class Bed:
    system: str
    D: str
    place: str  # "h" (depth below the surface) or "z" (height above the wall)
    pos: str
    mu: str
    kn: str
    gn: str
    seed: str

    @property
    def key(self):
        return scheme.key(scheme.BED, vars(self))

    @classmethod
    def parse(cls, key):
        m = scheme.parse(scheme.BED, key)
        if not m:
            raise ConfigError(f"not a bed path: '{key}' (expected {BED_PATTERN})")
        return cls(**m)

    def value(self, name):
        return number(getattr(self, name), f"bed {self.key}: {name}")

    @property
    def column_key(self):
        """The column a placed bed's intruder goes into: the bed but its D and depth."""
        return scheme.key(scheme.COLUMN, vars(self))


@dataclass(frozen=True)
class Pull:
    bed: Bed
    speed: str  # "Fr~1" or "V~0.01"
    settings: tuple = field(default=(), compare=False)  # sorted (key, value) pull overrides
    sweep: str = field(default="", compare=False)

    @property
    def key(self):
        return f"{self.bed.key}/{self.speed}"

    @property
    def V(self):
        kind, value = parse_speed(self.speed)
        return value if kind == "V" else froude_speed(value, self.bed.value("D"))

    def settings_in(self, config):
        """The pull's settings: its system's `pull` block with this pull's own over it."""
        settings = dict(config["systems"][self.bed.system].get("pull") or {})
        settings.update(dict(self.settings))
        return settings


# Where a job's output, benchmark and log go, under a study's `results` and `logs`: its kind's
# folder, its key (a bed's, a column's, or a pull's "<bed>/<speed>"), its file. Declared once;
# the rules spell their outputs, benchmarks and logs through these (a key may be a wildcard).
JOB_OUTPUTS = {"beds": "bed.h5", "columns": "column.h5", "pulls": "run.h5"}


def job_file(results, kind, key):
    """A job's output: job_file("r", "pulls", "<bed>/Fr~1") is "r/pulls/<bed>/Fr~1/run.h5"."""
    return f"{results}/{job_name(kind, key)}/{JOB_OUTPUTS[kind]}"


def benchmark_file(results, kind, key):
    """A job's benchmark (Snakemake's record of its CPU, wall time and memory)."""
    return f"{results}/benchmarks/{job_name(kind, key)}.tsv"


def log_file(logs, kind, key):
    return f"{logs}/{job_name(kind, key)}.log"


def job_name(kind, key):
    """A job as its benchmark and its log name it: "beds/<bed>", "pulls/<bed>/Fr~1"."""
    if kind not in JOB_OUTPUTS:
        raise ConfigError(f"not a kind of job: '{kind}' (one of {', '.join(JOB_OUTPUTS)})")
    return f"{kind}/{key}"


def bed_file(results, key):
    return job_file(results, "beds", key)


def column_bed(key):
    """A column's path as a Bed without intruder (D 0, no depth): what its pour and its cost read."""
    m = scheme.parse(scheme.COLUMN, key)
    if not m:
        raise ConfigError(f"not a column path: '{key}' (expected {COLUMN_PATTERN})")
    return Bed(D="0", place="h", pos="0", **m)


def column_file(results, key):
    return job_file(results, "columns", key)


def bed_pattern(systems):
    """BED_PATTERN restricted to the systems named (none: a pattern no path matches)."""
    return scheme.pattern(scheme.BED, system=systems)


def run_file(results, key):
    return job_file(results, "pulls", key)
