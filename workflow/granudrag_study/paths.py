"""Names of the study's jobs: a bed and a pull as paths whose numbers are their parameters.

A bed is identified by its system (box, grain count, pour settings), the intruder diameter
D, its placement (depth h below the free surface, or height z above the wall), friction mu,
K_n, gamma_n and the pour's seed; its path names all but the system's settings:

    <results>/beds/system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.054/seed~1/bed.h5

A system whose beds are placed (`placement:`) pours one column per seed, without an intruder,
and places each bed's intruder into it (granudrag place); the column's path is the bed's
without D and depth (the bed's path stays as above):

    <results>/columns/system~I/mu~0.5/kn~2e4/gn~199.054/seed~1/column.h5

A pull is a bed and a speed, given as a Froude number (Fr~) or a speed (V~):

    <results>/pulls/system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.054/seed~1/Fr~1/run.h5

Numbers in paths are written by `fmt` and the jobs use exactly the numbers the path states,
so a path is a complete, reproducible name.
"""

import math
import re
from dataclasses import dataclass, field

from analysis.physics import froude_speed

from .config import ConfigError

# Wildcard patterns (regexes) of one bed and one speed in a path.
BED_PATTERN = r"system~[^/~]+/D~[^/~]+/[hz]~[^/~]+/mu~[^/~]+/kn~[^/~]+/gn~[^/~]+/seed~[^/~]+"
SPEED_PATTERN = r"(Fr|V)~[^/~]+"
COLUMN_PATTERN = r"system~[^/~]+/mu~[^/~]+/kn~[^/~]+/gn~[^/~]+/seed~[^/~]+"
_BED_RE = re.compile(
    r"^system~(?P<system>[^/~]+)/D~(?P<D>[^/~]+)/(?P<place>[hz])~(?P<pos>[^/~]+)"
    r"/mu~(?P<mu>[^/~]+)/kn~(?P<kn>[^/~]+)/gn~(?P<gn>[^/~]+)/seed~(?P<seed>[^/~]+)$"
)
_SPEED_RE = re.compile(r"^(?P<kind>Fr|V)~(?P<value>[^/~]+)$")


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
    m = _SPEED_RE.match(text)
    if not m:
        raise ConfigError(f"not a speed: '{text}' (expected Fr~<number> or V~<number>)")
    return m.group("kind"), number(m.group("value"), f"speed {text}")


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
        return (
            f"system~{self.system}/D~{self.D}/{self.place}~{self.pos}/mu~{self.mu}"
            f"/kn~{self.kn}/gn~{self.gn}/seed~{self.seed}"
        )

    @classmethod
    def parse(cls, key):
        m = _BED_RE.match(key)
        if not m:
            raise ConfigError(f"not a bed path: '{key}' (expected {BED_PATTERN})")
        return cls(**m.groupdict())

    def value(self, name):
        return number(getattr(self, name), f"bed {self.key}: {name}")

    @property
    def column_key(self):
        """The column a placed bed's intruder goes into: the bed but its D and depth."""
        return f"system~{self.system}/mu~{self.mu}/kn~{self.kn}/gn~{self.gn}/seed~{self.seed}"


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


def bed_file(results, key):
    return f"{results}/beds/{key}/bed.h5"


_COLUMN_RE = re.compile(
    r"^system~(?P<system>[^/~]+)/mu~(?P<mu>[^/~]+)/kn~(?P<kn>[^/~]+)/gn~(?P<gn>[^/~]+)/seed~(?P<seed>[^/~]+)$"
)


def column_bed(key):
    """A column's path as a Bed without intruder (D 0, no depth): what its pour and its cost read."""
    m = _COLUMN_RE.match(key)
    if not m:
        raise ConfigError(f"not a column path: '{key}' (expected {COLUMN_PATTERN})")
    return Bed(D="0", place="h", pos="0", **m.groupdict())


def column_file(results, key):
    return f"{results}/columns/{key}/column.h5"


def bed_pattern(systems):
    """BED_PATTERN restricted to the systems named (none: a pattern no path matches)."""
    names = "|".join(re.escape(str(s)) for s in systems) or "(?!)"
    return BED_PATTERN.replace("system~[^/~]+", f"system~(?:{names})", 1)


def run_file(results, key):
    return f"{results}/pulls/{key}/run.h5"
