"""The study's plan: every bed and pull of a config's sweeps, and the pulls figures single out.

Adding a value to a sweep adds paths; the existing ones, and the beds they share, stay.
"""

import dataclasses
import itertools
import math
from collections import Counter
from dataclasses import dataclass, field

from analysis.core.physics import PAPER_RATIO, gamman_for

from .config import ConfigError, placed, resolve_beds_from
from .paths import Bed, Pull, fmt, parse_speed, speed_key

SWEEP_AXES = ("D", "depth", "z", "mu", "kn", "gamman", "gamman_ratio", "seed")


def _as_list(value):
    return list(value) if isinstance(value, (list, tuple)) else [value]


@dataclass
class Plan:
    config: dict
    beds: dict  # key -> Bed, in first-seen order
    pulls: dict  # key -> Pull
    columns: dict = field(default_factory=dict)  # column key -> its first placed Bed

    def pull_settings(self, bed_key, speed):
        """Pull overrides of the sweep that asked for this pull (none if no sweep did)."""
        p = self.pulls.get(f"{bed_key}/{speed}")
        return dict(p.settings) if p else {}


def _replicates(mapping, where):
    """`seeds: [1, 2, 3]` (replicate beds, one poured per seed) is `seed` by another name."""
    if "seeds" not in mapping:
        return mapping
    if "seed" in mapping:
        raise ConfigError(f"{where}: give 'seed' or 'seeds', not both (both list the beds' seeds)")
    out = {k: v for k, v in mapping.items() if k != "seeds"}
    out["seed"] = mapping["seeds"]
    return out


def _sweep_values(sweep, defaults, name, i):
    where = f"sweeps[{i}] ({name})"
    sweep, defaults = _replicates(sweep, where), _replicates(defaults, "defaults")
    merged = {k: defaults[k] for k in SWEEP_AXES if k in defaults}
    # A sweep's placement or damping replaces the defaults' as a whole.
    if "depth" in sweep or "z" in sweep:
        merged.pop("depth", None)
        merged.pop("z", None)
    if "gamman" in sweep or "gamman_ratio" in sweep:
        merged.pop("gamman", None)
        merged.pop("gamman_ratio", None)
    merged.update({k: sweep[k] for k in SWEEP_AXES if k in sweep})
    for k in ("D", "mu", "kn"):
        if k not in merged:
            raise ConfigError(f"{where}: no '{k}' (give it in the sweep or under 'defaults')")
    if "seed" not in merged:
        raise ConfigError(f"{where}: no 'seed' (give 'seed' or 'seeds', the beds' seeds, in the sweep "
                          f"or under 'defaults')")
    if ("depth" in merged) == ("z" in merged):
        raise ConfigError(
            f"{where}: give exactly one of 'depth' (below the free surface) and 'z' "
            f"(height above the wall), in the sweep or under 'defaults'"
        )
    if "gamman" in merged and "gamman_ratio" in merged:
        raise ConfigError(f"{where}: give 'gamman' or 'gamman_ratio', not both")
    if "Fr" not in sweep and "V" not in sweep:
        raise ConfigError(f"{where}: no speeds: give 'Fr' (Froude numbers) and/or 'V' (speeds)")
    return {k: _as_list(v) for k, v in merged.items()}


def poured_bed(bed, config):
    """The bed a pull of `bed.system` goes through: its own, or with `beds_from: A` system A's
    (the same path but for system~A)."""
    source = config["systems"][bed.system].get("beds_from")
    return bed if source is None else dataclasses.replace(bed, system=str(source))


def plan(config):
    """All beds and pulls of the config's sweeps (duplicates merged). A pull's `bed` names its
    own system (its path); the bed poured for it is `poured_bed(pull.bed, config)`."""
    resolve_beds_from(config)
    systems, defaults = config["systems"], config.get("defaults", {}) or {}
    beds, pulls, columns = {}, {}, {}
    _check_placed_systems(systems)
    for i, sweep in enumerate(config["sweeps"]):
        name = sweep.get("name", f"#{i}")
        where = f"sweeps[{i}] ({name})"
        system = str(sweep["system"])
        if system not in systems:
            raise ConfigError(
                f"{where}: system '{system}' is not defined under 'systems' "
                f"(defined: {', '.join(map(str, systems)) or 'none'})"
            )
        ax = _sweep_values(sweep, defaults, name, i)
        place, positions = ("h", ax["depth"]) if "depth" in ax else ("z", ax["z"])
        damping = ax.get("gamman") or [("ratio", r) for r in ax.get("gamman_ratio", [PAPER_RATIO])]
        speeds = [speed_key(kind, v) for kind in ("Fr", "V") for v in _as_list(sweep.get(kind, []))]
        settings = tuple(sorted((sweep.get("pull") or {}).items()))
        grid = itertools.product(ax["D"], positions, ax["mu"], ax["kn"], damping, ax["seed"])
        for D, pos, mu, kn, gn, seed in grid:
            kn_text = fmt(kn)
            gn_value = gamman_for(float(kn_text), gn[1]) if isinstance(gn, tuple) else gn
            bed = Bed(system, fmt(D), place, fmt(pos), fmt(mu), kn_text, fmt(gn_value), str(int(seed)))
            poured = poured_bed(bed, config)
            beds.setdefault(poured.key, poured)
            if placed(config, poured.system):
                if place != "h":
                    raise ConfigError(
                        f"{where}: system '{poured.system}' places its intruders into columns "
                        f"(placement), at a depth below the column's surface: give 'depth', not 'z'")
                columns.setdefault(poured.column_key, poured)
            for speed in speeds:
                pull = Pull(bed, speed, settings, name)
                old = pulls.get(pull.key)
                if old is not None and old.settings != settings:
                    raise ConfigError(
                        f"{where}: pull {pull.key} is also in sweep '{old.sweep}' with other pull "
                        f"settings ({dict(old.settings)} vs {dict(settings)}); one path, one pull"
                    )
                pulls.setdefault(pull.key, pull)
    if not pulls:
        raise ConfigError("sweeps: the config describes no pulls")
    _check_yield_speeds(config, pulls)
    return Plan(config, beds, pulls, columns)


# Pour keys that place an intruder: a placed system's column has none (give them under placement).
INTRUDER_POUR_KEYS = ("intruder_x", "intruder_y", "packing_estimate")


def _check_placed_systems(systems):
    for name, sysc in systems.items():
        if "placement" not in sysc or sysc.get("beds_from") is not None:
            continue
        for key in INTRUDER_POUR_KEYS:
            if key in (sysc.get("pour") or {}):
                where = f"config key 'systems.{name}.pour.{key}'"
                if key == "packing_estimate":
                    raise ConfigError(f"{where}: a placed system's column is poured without an "
                                      f"intruder, whose depth placement measures: remove it")
                raise ConfigError(f"{where}: a placed system's column is poured without an intruder: "
                                  f"give it under systems.{name}.placement")


def _check_yield_speeds(config, pulls):
    """With yield speeds per friction (report.yield_speed as {mu, V} steps), a pull at one of
    those speeds at a friction whose step names another is a yield pull the report would not
    read as F_Y, and the friction's F_Y then missing: an edit of one without the other (as
    re-pairing faithful.yaml's yield sweeps, R2). A validation study compares speeds on
    purpose and is not checked."""
    steps = (config.get("report") or {}).get("yield_speed")
    if not isinstance(steps, list) or config.get("validation"):
        return
    from analysis.core.table import yield_speeds

    speeds = {float(s["V"]) for s in steps}
    given = "[" + ", ".join(f"{{mu: {fmt(s['mu'])}, V: {fmt(s['V'])}}}" for s in steps) + "]"
    for pull in pulls.values():
        if parse_speed(pull.speed)[0] != "V" or not any(math.isclose(pull.V, v, rel_tol=1e-6) for v in speeds):
            continue
        mu = pull.bed.value("mu")
        wanted = float(yield_speeds(steps, [mu])[0])
        if not math.isclose(pull.V, wanted, rel_tol=1e-6):
            raise ConfigError(
                f"sweep '{pull.sweep}' pulls mu = {fmt(mu)} at V = {fmt(pull.V)}, a yield speed of "
                f"report.yield_speed {given}, which gives V = {fmt(wanted)} at that friction: its drag "
                f"would not be read as the yield force. Pull it at V = {fmt(wanted)}, or change "
                f"report.yield_speed (a comparison of speeds belongs in a validation study: "
                f"config/validate/yield_speed*.yaml)")


def log_grid(lo, hi, n):
    """n numbers from lo to hi evenly spaced in log, rounded to 3 significant digits."""
    n = int(n)
    return [float(f"{lo * (hi / lo) ** (i / (n - 1)):.3g}") for i in range(n)]


def reference_law(plan_):
    """(K_n, gamma_n) as path text of the contact law with the most pulls: the study's
    reference (Fig. 2 uses it)."""
    return Counter((p.bed.kn, p.bed.gn) for p in plan_.pulls.values()).most_common(1)[0][0]


def nearest_pull(plan_, system="I", D=4.0, mu=0.5, V=1.0):
    """The planned pull nearest to (system, D, mu, V): same system first, then mu, D, log V."""

    def distance(p):
        return (
            (p.bed.system != str(system)) * 100.0
            + abs(p.bed.value("mu") - float(mu)) * 10
            + abs(p.bed.value("D") - float(D))
            + abs(math.log(p.V / float(V)))
        )

    return min(plan_.pulls.values(), key=distance)


def trace_pull(plan_):
    """The pull whose force trace is Fig. 4: the config's report.trace if it is one
    of the pulls, else the system-I pull nearest to the paper's (D = 4, V = 1, mu = 0.5)."""
    want = dict((plan_.config.get("report") or {}).get("trace") or {})
    return nearest_pull(plan_, **want)


# Fig. 9 of the paper: (D, V) = (2, 0.1), (3, 1), (4, 3) at mu = 0.5 in system I.
PAPER_FLOW_FIELD = [{"D": 2.0, "V": 0.1}, {"D": 3.0, "V": 1.0}, {"D": 4.0, "V": 3.0}]


def flow_pulls(plan_):
    """The pulls whose velocity fields are the panels of Fig. 9 (report.flow_field, default the
    paper's three), each the nearest planned pull; a pull is listed once."""
    want = (plan_.config.get("report") or {}).get("flow_field") or PAPER_FLOW_FIELD
    chosen = [nearest_pull(plan_, **{"system": "I", "mu": 0.5, **w}) for w in want]
    return list(dict.fromkeys(chosen, None))
