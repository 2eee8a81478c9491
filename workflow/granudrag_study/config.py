"""A study config: its JSON schema check, with messages that name the bad key."""

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"


class ConfigError(ValueError):
    """A config that names no valid study; the message names the key."""


def validate_config(config, schema_path=SCHEMA):
    """Check config against the JSON schema; raise ConfigError naming the bad key.

    (The workflow then runs snakemake.utils.validate, which also fills in the schema's
    defaults; this check comes first for its shorter message.)
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
        lines.append(f"config key '{where or '(top level)'}': {_message(best, where)}")
    raise ConfigError("invalid config:\n  " + "\n  ".join(lines))


# The config's paths: any path the filesystem allows (the rules quote them for the shell) but
# one with braces, which Snakemake would read as wildcards (the schema's pattern).
PATH_KEYS = ("granudrag", "results", "logs")


def _message(err, where):
    if err.validator == "pattern" and where in PATH_KEYS:
        return (f"{err.instance!r} holds a brace ({{ or }}), which Snakemake reads as a wildcard "
                "in a file's name: choose a path without braces")
    return err.message


# What a system that pulls through another's beds (`beds_from`) takes from it: the bed's box,
# grains, pour and placement. Its own `pull` settings are laid over the other system's.
BED_KEYS = ("lx", "ly", "grains", "pour", "placement")


def resolve_beds_from(config):
    """Fill in, for each system with `beds_from: A`, system A's box, grains and pour (and A's
    pull settings under its own), so that every reader of `systems` sees a whole system; its
    beds stay A's (study.plan pours them once, under system~A). Such systems exist for paired
    comparisons of pull settings through the same beds (config/validate/active_region.yaml).
    Idempotent; raises ConfigError naming the key."""
    systems = config.get("systems") or {}
    for name, sysc in systems.items():
        source = sysc.get("beds_from")
        if source is None:
            continue
        source = str(source)
        where = f"config key 'systems.{name}.beds_from'"
        if source not in map(str, systems):
            raise ConfigError(f"{where}: no system '{source}' (defined: {', '.join(map(str, systems))})")
        origin = systems[source] if source in systems else systems[int(source)]
        if str(source) == str(name):
            raise ConfigError(f"{where}: a system cannot take its beds from itself")
        if origin.get("beds_from") is not None:
            raise ConfigError(f"{where}: system '{source}' itself pulls through system "
                              f"'{origin['beds_from']}''s beds: name that one")
        for key in BED_KEYS:
            if key in origin and key in sysc and sysc[key] != origin[key]:
                raise ConfigError(f"config key 'systems.{name}.{key}': a system with beds_from takes "
                                  f"its beds' {key} from system '{source}'; remove it")
            if key in origin:
                sysc[key] = origin[key]
        # The same protocol but for what this system changes: its pull settings over A's.
        sysc["pull"] = {**(origin.get("pull") or {}), **(sysc.get("pull") or {})}
    return config


def resolve_binary(config, repo=REPO):
    """The config's `granudrag`, relative to the repository unless absolute."""
    path = Path(str(config["granudrag"]))
    return path if path.is_absolute() else (Path(repo) / path)


def fit_options(config):
    """The fits' options (analysis.fits.fitset.Options) from a validated config's `report` keys:
    n_boot, seed, h_min (Eq. 12 and Fig. 19 depth cut) and alpha_speeds."""
    from analysis.core.result import N_BOOT
    from analysis.fits.alpha_drag import ALPHA_SPEEDS
    from analysis.fits.fitset import Options

    rep = config.get("report") or {}
    return Options(n_boot=int(rep.get("n_boot", N_BOOT)), seed=int(rep.get("seed", 0)),
                   h_min=float(rep.get("h_min", 0.0) or 0.0),
                   alpha_speeds=tuple(float(v) for v in rep.get("alpha_speeds", ALPHA_SPEEDS)))


# granudrag pour's max_settle_time when a system sets none (its --help, the schema's default):
# a pour settles at most this long.
SETTLE_TIME_DEFAULT = 100.0
# granudrag pour's and place's settle_damping when unset (off: the paper's pour).
SETTLE_DAMPING_DEFAULT = 0.0


def pour_settings(config, system):
    """A system's `pour` block, its granudrag pour settings ({} when it has none)."""
    return dict(config["systems"][system].get("pour") or {})


def settle_limit(config, system):
    """The longest a system's pours settle: its max_settle_time."""
    return float(pour_settings(config, system).get("max_settle_time", SETTLE_TIME_DEFAULT))


# granudrag place's max_settle_time when a system's `placement` sets none (its --help).
PLACE_SETTLE_TIME_DEFAULT = 20.0
# granudrag place's min_settle_time when the placement sets none.
PLACE_MIN_SETTLE_TIME_DEFAULT = 1.0


def placed(config, system):
    """Whether a system's beds are made by placement (`placement:`, possibly {}): an intruder
    placed into a column poured once per seed without one (granudrag place)."""
    return "placement" in config["systems"][system]


def placement_settings(config, system):
    """A system's `placement` block, its granudrag place settings ({} when it has none)."""
    return dict(config["systems"][system].get("placement") or {})


def place_limit(config, system):
    """The longest a system's placements settle: its placement's max_settle_time."""
    return float(placement_settings(config, system).get("max_settle_time", PLACE_SETTLE_TIME_DEFAULT))
