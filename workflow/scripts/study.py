"""The study's jobs from the config: beds, pulls, their paths, arguments and cost.

Imported by workflow/rules/common.smk and by estimate_cost.py; plain Python
(no Snakemake), so it is tested on its own.

A bed is identified by its system (box, grain count, pour settings), the
intruder diameter D, its placement (depth h below the free surface, or
height z above the wall), friction mu, K_n, gamma_n and the pour's seed;
its path names all but the system's settings:

    <results>/beds/system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.054/seed~1/bed.h5

A pull is a bed and a speed, given as a Froude number (Fr~) or a speed (V~):

    <results>/pulls/system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.054/seed~1/Fr~1/run.h5

Numbers in paths are written by `fmt` and the jobs use exactly the numbers
the path states, so a path is a complete, reproducible name. Adding a value
to a sweep adds paths; the existing ones, and the beds they share, stay.
"""
import itertools
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

PAPER_KN, PAPER_GAMMAN = 2e8, 5e4
PAPER_RATIO = PAPER_GAMMAN / PAPER_KN ** 0.6     # gamma_n / K_n^0.6 of the paper
YIELD_SPEED = 0.01

# Wildcard patterns (regexes) of one bed and one speed in a path.
BED_PATTERN = (r"system~[^/~]+/D~[^/~]+/[hz]~[^/~]+/mu~[^/~]+/kn~[^/~]+/gn~[^/~]+/seed~[^/~]+")
SPEED_PATTERN = r"(Fr|V)~[^/~]+"
_BED_RE = re.compile(r"^system~(?P<system>[^/~]+)/D~(?P<D>[^/~]+)/(?P<place>[hz])~(?P<pos>[^/~]+)"
                     r"/mu~(?P<mu>[^/~]+)/kn~(?P<kn>[^/~]+)/gn~(?P<gn>[^/~]+)/seed~(?P<seed>[^/~]+)$")
_SPEED_RE = re.compile(r"^(?P<kind>Fr|V)~(?P<value>[^/~]+)$")

SWEEP_AXES = ("D", "depth", "z", "mu", "kn", "gamman", "gamman_ratio", "seed")


class ConfigError(ValueError):
    """A config that names no valid study; the message names the key."""


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


def gamman_for(kn, ratio=PAPER_RATIO):
    """gamma_n that keeps gamma_n / K_n^0.6 at ratio (the same restitution curve)."""
    return ratio * kn ** 0.6


def froude_speed(Fr, D):
    """Speed V of Froude number Fr (paper Eq. 4) for intruder diameter D."""
    return Fr * (D + 1.0) / (2.0 * math.sqrt(2.0 * D))


def hertz_dt(kn):
    """granudrag's default time step: the Hertz collision time of two 0.9 d grains
    meeting at 10 sqrt(gd), over 64; it scales as K_n^-0.4 (value printed by
    `granudrag pour` at K_n = 2e4: 4.1962e-4; at 2e8: 1.054e-5)."""
    return 4.1962350679e-4 * (float(kn) / 2e4) ** -0.4


@dataclass(frozen=True)
class Bed:
    system: str
    D: str
    place: str          # "h" (depth below the surface) or "z" (height above the wall)
    pos: str
    mu: str
    kn: str
    gn: str
    seed: str

    @property
    def key(self):
        return (f"system~{self.system}/D~{self.D}/{self.place}~{self.pos}/mu~{self.mu}"
                f"/kn~{self.kn}/gn~{self.gn}/seed~{self.seed}")

    @classmethod
    def parse(cls, key):
        m = _BED_RE.match(key)
        if not m:
            raise ConfigError(f"not a bed path: '{key}' (expected {BED_PATTERN})")
        return cls(**m.groupdict())

    def value(self, name):
        return number(getattr(self, name), f"bed {self.key}: {name}")


@dataclass(frozen=True)
class Pull:
    bed: Bed
    speed: str          # "Fr~1" or "V~0.01"
    settings: tuple = field(default=(), compare=False)   # sorted (key, value) pull overrides
    sweep: str = field(default="", compare=False)

    @property
    def key(self):
        return f"{self.bed.key}/{self.speed}"

    @property
    def V(self):
        kind, value = parse_speed(self.speed)
        return value if kind == "V" else froude_speed(value, self.bed.value("D"))


def log_grid(lo, hi, n):
    """n numbers from lo to hi evenly spaced in log, rounded to 3 significant digits."""
    n = int(n)
    return [float(f"{lo * (hi / lo) ** (i / (n - 1)):.3g}") for i in range(n)]


def parse_speed(text):
    m = _SPEED_RE.match(text)
    if not m:
        raise ConfigError(f"not a speed: '{text}' (expected Fr~<number> or V~<number>)")
    return m.group("kind"), number(m.group("value"), f"speed {text}")


def _as_list(value):
    return list(value) if isinstance(value, (list, tuple)) else [value]


@dataclass
class Plan:
    config: dict
    beds: dict                 # key -> Bed, in first-seen order
    pulls: dict                # key -> Pull

    def pull_settings(self, bed_key, speed):
        """Pull overrides of the sweep that asked for this pull (none if no sweep did)."""
        p = self.pulls.get(f"{bed_key}/{speed}")
        return dict(p.settings) if p else {}


def _sweep_values(sweep, defaults, name, i):
    where = f"sweeps[{i}] ({name})"
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
    if ("depth" in merged) == ("z" in merged):
        raise ConfigError(f"{where}: give exactly one of 'depth' (below the free surface) and 'z' "
                          f"(height above the wall), in the sweep or under 'defaults'")
    if "gamman" in merged and "gamman_ratio" in merged:
        raise ConfigError(f"{where}: give 'gamman' or 'gamman_ratio', not both")
    if "Fr" not in sweep and "V" not in sweep:
        raise ConfigError(f"{where}: no speeds: give 'Fr' (Froude numbers) and/or 'V' (speeds)")
    return {k: _as_list(v) for k, v in merged.items()}


def plan(config):
    """All beds and pulls of the config's sweeps (duplicates merged)."""
    systems, defaults = config["systems"], config.get("defaults", {}) or {}
    beds, pulls = {}, {}
    for i, sweep in enumerate(config["sweeps"]):
        name = sweep.get("name", f"#{i}")
        where = f"sweeps[{i}] ({name})"
        system = str(sweep["system"])
        if system not in systems:
            raise ConfigError(f"{where}: system '{system}' is not defined under 'systems' "
                              f"(defined: {', '.join(map(str, systems)) or 'none'})")
        ax = _sweep_values(sweep, defaults, name, i)
        place, positions = ("h", ax["depth"]) if "depth" in ax else ("z", ax["z"])
        damping = ax.get("gamman") or [("ratio", r) for r in ax.get("gamman_ratio", [PAPER_RATIO])]
        speeds = [f"Fr~{fmt(v)}" for v in _as_list(sweep.get("Fr", []))] + \
                 [f"V~{fmt(v)}" for v in _as_list(sweep.get("V", []))]
        settings = tuple(sorted((sweep.get("pull") or {}).items()))
        for D, pos, mu, kn, gn, seed in itertools.product(ax["D"], positions, ax["mu"], ax["kn"],
                                                          damping, ax["seed"]):
            kn_text = fmt(kn)
            gn_value = gamman_for(float(kn_text), gn[1]) if isinstance(gn, tuple) else gn
            bed = Bed(system, fmt(D), place, fmt(pos), fmt(mu), kn_text, fmt(gn_value),
                      str(int(seed)))
            beds.setdefault(bed.key, bed)
            for speed in speeds:
                pull = Pull(bed, speed, settings, name)
                old = pulls.get(pull.key)
                if old is not None and old.settings != settings:
                    raise ConfigError(
                        f"{where}: pull {pull.key} is also in sweep '{old.sweep}' with other pull "
                        f"settings ({dict(old.settings)} vs {dict(settings)}); one path, one pull")
                pulls.setdefault(pull.key, pull)
    if not pulls:
        raise ConfigError("sweeps: the config describes no pulls")
    return Plan(config, beds, pulls)


# --- command lines ----------------------------------------------------------

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
    sysc = config["systems"][bed.system]
    args = ["--lx", fmt(sysc["lx"]), "--ly", fmt(sysc["ly"]), "--grains", str(int(sysc["grains"])),
            "--intruder_diameter", bed.D,
            "--depth" if bed.place == "h" else "--intruder_z", bed.pos,
            "--mu", bed.mu, "--kn", bed.kn, "--gamman", bed.gn, "--seed", bed.seed]
    return args + _flags(sysc.get("pour") or {})


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
        gap = min(gap, int(config["max_runtime"]) / 4.0)   # several checkpoints per job
    pieces = math.ceil(minutes / gap)
    if pieces <= 10:
        return None
    return float(f"{pull_distance(pull, config) / pull.V / pieces:.4g}")


def job_attempts(minutes, config):
    """Jobs needed for a run of `minutes` estimated wall time under max_runtime: its time
    limit doubles per retry up to the cap, and each retry resumes from the checkpoint."""
    cap = config.get("max_runtime")
    if not cap:
        return 1
    limit, done, attempts = minutes, 0.0, 0
    while done < minutes:
        attempts += 1
        done += min(limit * 2 ** (attempts - 1), cap) * 0.75    # a quarter lost to restarts
    return attempts


# --- cost -------------------------------------------------------------------

def bed_dt(bed, config):
    dt = (config["systems"][bed.system].get("pour") or {}).get("dt")
    return float(dt) if dt else hertz_dt(bed.value("kn"))


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


def job_resources(cost, grains, config, attempt=1):
    """(mem_mb, runtime in minutes) for a job: a generous bound for schedulers, doubled on
    each retry (a time limit is the likely reason; the retry resumes from the checkpoint),
    at most max_runtime."""
    mem = int(200 + 0.004 * grains)          # ~1.5 kB per grain measured; x2.5 margin
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


def nearest_pull(plan_, system="I", D=4.0, mu=0.5, V=1.0):
    """The planned pull nearest to (system, D, mu, V): same system first, then mu, D, log V."""
    def distance(p):
        return ((p.bed.system != str(system)) * 100.0 + abs(p.bed.value("mu") - float(mu)) * 10
                + abs(p.bed.value("D") - float(D)) + abs(math.log(p.V / float(V))))
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


def summary(plan_):
    """Numbers of jobs and estimated particle-steps and core-hours."""
    config = plan_.config
    bed_ps = sum(bed_cost(b, config) for b in plan_.beds.values())
    pull_ps = sum(pull_cost(p, config) for p in plan_.pulls.values())
    threads = int(config["threads"])
    core_h = (bed_ps + pull_ps) / float(config["throughput"]) * threads / 3600.0
    return {"beds": len(plan_.beds), "pulls": len(plan_.pulls),
            "bed_particle_steps": bed_ps, "pull_particle_steps": pull_ps,
            "core_hours": core_h, "threads": threads}


def resolve_binary(config, repo):
    path = Path(str(config["granudrag"]))
    return path if path.is_absolute() else (Path(repo) / path)


def validate_config(config, schema_path):
    """Check config against the JSON schema; raise ConfigError naming the bad key.

    (common.smk then runs snakemake.utils.validate, which also fills in the
    schema's defaults; this check comes first for its shorter message.)
    """
    import jsonschema
    import yaml
    with open(schema_path) as fh:
        schema = yaml.safe_load(fh)
    validator = jsonschema.Draft7Validator(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: list(map(str, e.absolute_path)))
    if not errors:
        return
    lines = []
    for err in errors:
        best = jsonschema.exceptions.best_match([err])
        where = ""
        for part in best.absolute_path:
            where += f"[{part}]" if isinstance(part, int) else (f".{part}" if where else str(part))
        lines.append(f"config key '{where or '(top level)'}': {best.message}")
    raise ConfigError("invalid config:\n  " + "\n  ".join(lines))
