# Config validation, the study's plan (beds and pulls) and helpers of the rules. The
# library behind them is analysis.study (plain Python, tested on its own).

from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from analysis import figure_list, study

REPO = Path(workflow.basedir).parent

try:
    # First our check, whose messages name the bad key in one line ...
    study.validate_config(config, REPO / "workflow" / "schemas" / "config.schema.yaml")
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


wildcard_constraints:
    bed=study.BED_PATTERN,
    speed=study.SPEED_PATTERN,


def bed_file(key):
    return study.bed_file(RESULTS, key)


def run_file(key):
    return study.run_file(RESULTS, key)


ALL_BEDS = [bed_file(k) for k in PLAN.beds]
ALL_RUNS = [run_file(k) for k in PLAN.pulls]
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
    assert name in figure_list.NAMES, name
    return report(
        f"{REPORT}/{name}.png",
        caption=f"../report/{name}.rst",
        category="Figures",
        subcategory=subcategory,
    )


def _bed(wildcards):
    return study.Bed.parse(wildcards.bed)


def pour_args(wildcards):
    return " ".join(study.pour_args(_bed(wildcards), config))


def pull_args(wildcards):
    return " ".join(study.pull_args(_bed(wildcards), wildcards.speed, PLAN))


def _grains(wildcards):
    return int(config["systems"][_bed(wildcards).system]["grains"])


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


onsuccess:
    results = Path(RESULTS).resolve()
    print(
        f"granudrag: report at {results}/report/report.html (and report.md), table at {results}/table.csv"
    )


def figure_files(subcategory, *names):
    """Output files of figures: each one's PNG (in Snakemake's report) and PDF, and Table I's
    Markdown."""
    files = []
    for name in names:
        files += [figure(name, subcategory), f"{REPORT}/{name}.pdf"]
        if figure_list.BY_NAME[name].markdown:
            files.append(f"{REPORT}/{name}.md")
    return files
