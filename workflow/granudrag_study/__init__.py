"""The study library of the Snakemake workflow (workflow/Snakefile): plain Python, no
Snakemake, so it is tested on its own (tests/workflow/test_study.py).

    config    the config's schema check (ConfigError names the bad key), the engine's path
    paths     a bed and a pull as paths whose numbers are their parameters (Bed, Pull, fmt),
              from the one declaration of the path's components (analysis.core.path_scheme)
    plan      every bed and pull of the config's sweeps; the pulls of Figs. 4 and 9
    cost      estimated particle-steps and wall time of each job, scheduler resources
    region_cost  what the active region saves a pull: sleeping fractions measured, a model
    commands  `granudrag pour` / `place` / `pull` arguments of a job
    estimate  the job count and cost of a config (command line)
    script    the common start of the workflow's scripts (logging to the rule's log)
    failures  a failed job's record and the placeholders of table.allow_failed
    manifest  the plan's pulls as a file, so a grown sweep remakes the table by file time alone

The names below are the library's interface: `import granudrag_study as study; study.plan(config)`.
"""

from .commands import (
    checkpoint_interval,
    column_args,
    movie_pull_args,
    place_args,
    pour_args,
    pour_checkpoint_interval,
    pull_args,
)
from .config import (
    PATH_KEYS,
    SCHEMA,
    SETTLE_TIME_DEFAULT,
    ConfigError,
    fit_options,
    place_limit,
    placed,
    placement_settings,
    pour_settings,
    resolve_beds_from,
    resolve_binary,
    settle_limit,
    validate_config,
)
from .cost import (
    bed_cost,
    bed_dt,
    bed_retries,
    column_cost,
    expected_bed_cost,
    expected_column_cost,
    expected_place_time,
    expected_pull_cost,
    expected_settle_time,
    job_attempts,
    job_resources,
    job_seconds,
    pull_cost,
    pull_distance,
    pull_retries,
    pull_time,
    pull_work,
    summary,
)
from .manifest import plan_file, write_plan
from .paths import (
    BED_PATTERN,
    COLUMN_PATTERN,
    SPEED_PATTERN,
    Bed,
    Pull,
    bed_file,
    bed_pattern,
    column_bed,
    column_file,
    fmt,
    number,
    parse_speed,
    run_file,
    speed_key,
)
from .plan import (
    PAPER_FLOW_FIELD,
    SWEEP_AXES,
    Plan,
    flow_pulls,
    log_grid,
    nearest_pull,
    plan,
    poured_bed,
    reference_law,
    trace_pull,
)

__all__ = [
    "BED_PATTERN",
    "COLUMN_PATTERN",
    "PAPER_FLOW_FIELD",
    "PATH_KEYS",
    "SCHEMA",
    "SETTLE_TIME_DEFAULT",
    "SPEED_PATTERN",
    "SWEEP_AXES",
    "Bed",
    "ConfigError",
    "Plan",
    "Pull",
    "bed_cost",
    "bed_dt",
    "bed_retries",
    "bed_file",
    "bed_pattern",
    "column_args",
    "column_bed",
    "column_cost",
    "column_file",
    "expected_column_cost",
    "expected_place_time",
    "place_args",
    "place_limit",
    "placed",
    "placement_settings",
    "checkpoint_interval",
    "fit_options",
    "flow_pulls",
    "fmt",
    "job_attempts",
    "job_resources",
    "job_seconds",
    "log_grid",
    "nearest_pull",
    "number",
    "parse_speed",
    "speed_key",
    "plan",
    "plan_file",
    "poured_bed",
    "pour_settings",
    "pour_args",
    "pour_checkpoint_interval",
    "pull_args",
    "movie_pull_args",
    "pull_cost",
    "expected_pull_cost",
    "expected_bed_cost",
    "expected_settle_time",
    "pull_distance",
    "pull_retries",
    "pull_time",
    "pull_work",
    "reference_law",
    "write_plan",
    "resolve_beds_from",
    "resolve_binary",
    "run_file",
    "settle_limit",
    "summary",
    "trace_pull",
    "validate_config",
]
