# Config validation, the study's plan (beds and pulls) and helpers of the rules. The
# library behind them is granudrag_study (plain Python, tested on its own).

import os
import shlex
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from analysis.figures import figure_names
import granudrag_study as study
from granudrag_study import failures

REPO = Path(workflow.basedir).parent

try:
    # First our check, whose messages name the bad key in one line ...
    study.validate_config(config, REPO / "workflow" / "schemas" / "config.schema.yaml")
    # A system with beds_from takes its box, grains and pour from the system named.
    study.resolve_beds_from(config)
except study.ConfigError as exc:
    raise WorkflowError(str(exc)) from None
# ... then Snakemake's, which also fills in the schema's defaults.
validate(config, schema="../schemas/config.schema.yaml")

try:
    PLAN = study.plan(config)
except study.ConfigError as exc:
    raise WorkflowError(f"invalid config: {exc}") from None

RESULTS = config["results"].rstrip("/")
LOGS = config["logs"].rstrip("/")
REPORT = f"{RESULTS}/report"
GRANUDRAG = str(study.resolve_binary(config, REPO))
THREADS = config["threads"]
PULL_RETRIES = study.pull_retries(PLAN)  # None: the profile's restart-times
BED_RETRIES = study.bed_retries(PLAN)
# table.allow_failed: a pull that the engine stops (exit status 1) leaves a placeholder for the
# table and the report to list instead of failing its job (scripts/resumable.sh reads this; an
# environment variable, not a param, so that the pull rule and its jobs' records are unchanged).
os.environ.update(
    GRANUDRAG_ALLOW_FAILED="1" if config["table"]["allow_failed"] else "0"
)


wildcard_constraints:
    bed=study.BED_PATTERN,
    column=study.COLUMN_PATTERN,
    speed=study.SPEED_PATTERN,


# Systems whose beds are placed (`placement:`) into a column poured once per seed (rules column and
# placed_bed); the others' beds are poured (rule bed). A system with beds_from makes no beds.
PLACED = [str(n) for n in config["systems"] if study.placed(config, str(n))]
POURED_BED = study.bed_pattern(
    [str(n) for n in config["systems"] if str(n) not in PLACED]
)
PLACED_BED = study.bed_pattern(PLACED)


def bed_file(key):
    return study.bed_file(RESULTS, key)


def run_file(key):
    return study.run_file(RESULTS, key)


ALL_BEDS = [bed_file(k) for k in PLAN.beds]
ALL_COLUMNS = [study.column_file(RESULTS, k) for k in PLAN.columns]
ALL_RUNS = [run_file(k) for k in PLAN.pulls]
# The table's input with ALL_RUNS: rewritten only when the list of pulls changes, so a grown
# sweep remakes the table even where Snakemake has no metadata (granudrag_study/manifest.py).
try:
    PLAN_FILE = study.write_plan(RESULTS, PLAN.pulls)
except OSError as exc:
    raise WorkflowError(
        f"cannot write the study's list of pulls under results: {RESULTS} ({exc}); "
        "the results directory must be writable (the config's `results` key)"
    ) from None
TRACE_RUN = run_file(study.trace_pull(PLAN).key)
FLOW_RUNS = [run_file(p.key) for p in study.flow_pulls(PLAN)]

# The contact law with the most pulls: the study's reference (Fig. 2 uses it).
REFERENCE_LAW = study.reference_law(PLAN)
RESTITUTION_SPEEDS = study.log_grid(
    config["restitution"]["v_min"],
    config["restitution"]["v_max"],
    config["restitution"]["points"],
)


def figure(name, subcategory):
    """A figure's PNG in the report directory, in Snakemake's report with its own caption
    (workflow/report/<name>.rst)."""
    assert name in figure_names.NAMES, name
    return report(
        f"{REPORT}/{name}.png",
        caption=f"../report/{name}.rst",
        category="Figures",
        subcategory=subcategory,
    )


def _bed(wildcards):
    return study.Bed.parse(wildcards.bed)


def poured_bed_file(wildcards):
    """The bed a pull goes through: its system's, or with beds_from the other system's."""
    return bed_file(study.poured_bed(_bed(wildcards), config).key)


# Arguments as one shell-quoted string (shlex.join): the rules pass it whole to resumable.sh,
# which keeps it beside the checkpoint ({params.args:q}), and split to granudrag ({params.args}).
def pour_args(wildcards):
    return shlex.join(study.pour_args(_bed(wildcards), config))


def pull_args(wildcards):
    return shlex.join(study.pull_args(_bed(wildcards), wildcards.speed, PLAN))


def _grains(wildcards):
    return int(config["systems"][_bed(wildcards).system]["grains"])


def _column(wildcards):
    return study.column_bed(wildcards.column)


def column_args(wildcards):
    return shlex.join(study.column_args(_column(wildcards), config))


def column_of_bed(wildcards):
    """The column a placed bed's intruder goes into."""
    return study.column_file(RESULTS, _bed(wildcards).column_key)


def place_args(wildcards):
    return shlex.join(study.place_args(_bed(wildcards), config))


def column_mem_mb(wildcards):
    column = _column(wildcards)
    grains = int(config["systems"][column.system]["grains"])
    return study.job_resources(study.column_cost(column, config), grains, config)[0]


def column_runtime(wildcards, attempt):
    """Minutes, as bed_runtime."""
    column = _column(wildcards)
    grains = int(config["systems"][column.system]["grains"])
    return study.job_resources(
        study.column_cost(column, config), grains, config, attempt
    )[1]


def bed_mem_mb(wildcards):
    cost = study.bed_cost(_bed(wildcards), config)
    return study.job_resources(cost, _grains(wildcards), config)[0]


def bed_runtime(wildcards, attempt):
    """Minutes; doubled on each retry (a cluster time limit is the likely reason)."""
    cost = study.bed_cost(_bed(wildcards), config)
    return study.job_resources(cost, _grains(wildcards), config, attempt)[1]


def _pull(wildcards):
    bed = _bed(wildcards)
    return PLAN.pulls.get(f"{bed.key}/{wildcards.speed}") or study.Pull(
        bed, wildcards.speed
    )


def pull_mem_mb(wildcards):
    cost = study.pull_cost(_pull(wildcards), config)
    return study.job_resources(cost, _grains(wildcards), config)[0]


def pull_runtime(wildcards, attempt):
    """Minutes; doubled on each retry, which resumes from the pull's checkpoint (at most
    max_runtime: a longer pull goes on over several jobs)."""
    cost = study.pull_cost(_pull(wildcards), config)
    return study.job_resources(cost, _grains(wildcards), config, attempt)[1]


def end_of_run(succeeded):
    """Say which pulls failed; remove their placeholders (table.allow_failed) and the table's
    failed_pulls.txt, so that the next run makes the table again and retries them
    (workflow/granudrag_study/failures.py)."""
    failed = [run for run in ALL_RUNS if failures.read_failure(run) is not None]
    if failures.remove_placeholders(ALL_RUNS):
        Path(f"{RESULTS}/failed_pulls.txt").unlink(missing_ok=True)
    # What the targets asked for made (a validation study makes no report).
    if succeeded:
        results = Path(RESULTS).resolve()
        made = [
            f"{what} at {path}"
            for what, path in (
                ("report", results / "report" / "report.html"),
                ("table", results / "table.csv"),
            )
            if path.is_file()
        ]
        if made:
            print("granudrag: " + ", ".join(made))
    if failed:
        print(
            f"granudrag: {len(failed)} of {len(ALL_RUNS)} pulls failed, each with its reason in"
            " run.h5.failed beside where its run file belongs (and listed in"
            f" {RESULTS}/table_problems.txt when the table was made); run the same command again"
            " to retry them:\n  "
            + "\n  ".join(failures.describe(r, RESULTS) for r in failed)
        )


onsuccess:
    end_of_run(True)


onerror:
    end_of_run(False)


def figure_files(subcategory, *names):
    """Output files of figures: each one's PNG (in Snakemake's report), PDF and the data it
    plots (CSV), and Table I's Markdown."""
    files = []
    for name in names:
        files += [
            figure(name, subcategory),
            f"{REPORT}/{name}.pdf",
            f"{REPORT}/{name}.csv",
        ]
        if figure_names.BY_NAME[name].markdown:
            files.append(f"{REPORT}/{name}.md")
    return files
