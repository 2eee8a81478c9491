"""Paths that reach a shell (issue 76): the rules quote every path and argument.

- The smoke study, to its table and fits, from a checkout whose path holds a space, quotes and a
  non-ASCII letter, with results and logs directories named likewise.
- A config whose paths hold `;`, `$(...)` and backquotes runs nothing of them: a pour, the
  restitution curve and their logs land under those names, literally.
- A path with braces (Snakemake's wildcards) is refused by the config check, naming the key.

Under Snakemake 9 and 7.21 alike (GRANUDRAG_SNAKEMAKE, workflow_support.py).

And the path scheme itself (issue 75): the smoke study's files at the paths they always had, and
every kind of path (bed, column, pull) formatted, matched and parsed back to the same fields, all
from the one declaration in analysis.core.path_scheme.
"""
import dataclasses
import json
import re
import shutil
import subprocess

import pandas as pd
import pytest
from workflow_support import (
    BINARY,
    NEEDS_SNAKEMAKE_AND_ENGINE,
    ROOT,
    SNAKEMAKE,
    command,
    smoke_config,
    snakemake,
    write_config,
)

import granudrag_study as study
from analysis.core import path_scheme

# The smoke study's files as studies on disk hold them: a change of the scheme must not move them.
SMOKE_FILES = """
beds/system~I/D~1.5/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5
beds/system~I/D~2/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5
beds/system~II/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5
beds/system~II/D~2/h~5/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5
beds/system~II/D~2/h~5/mu~0.5/kn~5e4/gn~344.93242/seed~1/bed.h5
beds/system~II/D~2/h~5/mu~0.5/kn~5e4/gn~344.93242/seed~2/bed.h5
pulls/system~I/D~1.5/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~0.5/run.h5
pulls/system~I/D~1.5/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~1/run.h5
pulls/system~I/D~1.5/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~2/run.h5
pulls/system~I/D~2/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~0.5/run.h5
pulls/system~I/D~2/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~1/run.h5
pulls/system~I/D~2/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~2/run.h5
pulls/system~I/D~2/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/V~0.01/run.h5
pulls/system~II/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~1/run.h5
pulls/system~II/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~1/V~0.01/run.h5
pulls/system~II/D~2/h~5/mu~0.5/kn~2e4/gn~199.05359/seed~1/Fr~1/run.h5
pulls/system~II/D~2/h~5/mu~0.5/kn~2e4/gn~199.05359/seed~1/V~0.01/run.h5
pulls/system~II/D~2/h~5/mu~0.5/kn~5e4/gn~344.93242/seed~1/Fr~1/run.h5
pulls/system~II/D~2/h~5/mu~0.5/kn~5e4/gn~344.93242/seed~2/Fr~1/run.h5
""".split()


def test_the_smoke_studys_files_stay_where_they_are():
    plan = study.plan(smoke_config())
    files = [study.bed_file("r", k) for k in plan.beds] + [study.run_file("r", k) for k in plan.pulls]
    assert sorted(files) == [f"r/{f}" for f in SMOKE_FILES] and not plan.columns


def test_bed_column_and_pull_paths_round_trip_through_pattern_regex_and_key():
    bed = study.Bed("I", "3", "z", "13.5", "0.5", "2e6", "3154.7867", "1")
    assert [f.name for f in dataclasses.fields(study.Bed)] == [
        f for c in path_scheme.BED for f in ((c.choice,) if c.choice else ()) + (c.field,)]
    key = "system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~3154.7867/seed~1"
    assert bed.key == key and study.Bed.parse(key) == bed and re.fullmatch(study.BED_PATTERN, key)
    assert study.bed_file("results/x", key) == f"results/x/beds/{key}/bed.h5"
    deep = study.Bed("I", "2", "h", "7", "0.5", "2e4", "199.05359", "2")
    assert deep.key == "system~I/D~2/h~7/mu~0.5/kn~2e4/gn~199.05359/seed~2" == study.Bed.parse(deep.key).key
    for kind, value, text in (("Fr", 4, "Fr~4"), ("V", 0.1, "V~0.1")):
        speed = study.speed_key(kind, value)
        assert speed == text and study.parse_speed(speed) == (kind, value) and re.fullmatch(study.SPEED_PATTERN, speed)
        assert study.run_file("results/x", study.Pull(bed, speed).key) == f"results/x/pulls/{key}/{text}/run.h5"
    column = "system~I/mu~0.5/kn~2e6/gn~3154.7867/seed~1"
    assert bed.column_key == column and re.fullmatch(study.COLUMN_PATTERN, column)
    assert study.column_bed(column) == dataclasses.replace(bed, D="0", place="h", pos="0")
    assert study.column_bed(column).column_key == column
    assert study.column_file("results", column) == f"results/columns/{column}/column.h5"
    assert re.fullmatch(study.bed_pattern(["I"]), key) and not re.fullmatch(study.bed_pattern(["II"]), key)
    for bad, parse in ((column, study.Bed.parse), (key, study.column_bed), ("F~1", study.parse_speed)):
        with pytest.raises(study.ConfigError, match="not a"):
            parse(bad)


ODD = "my dir's \"é\" checkout"          # a space, both quotes, a non-ASCII letter


def checkout(where):
    """The workflow (its Snakefile, rules, scripts, schemas) and the engine (a link to the one
    under test, at build/granudrag) copied under `where`: a checkout as the rules see it."""
    where.mkdir(parents=True)
    shutil.copytree(ROOT / "workflow", where / "workflow",
                    ignore=shutil.ignore_patterns("__pycache__", ".snakemake"))
    (where / "build").mkdir()
    (where / "build" / "granudrag").symlink_to(BINARY)
    return where


@pytest.mark.parametrize("key", study.PATH_KEYS)
def test_a_path_with_braces_is_refused_naming_the_key(key):
    config = smoke_config()
    config[key] = "out{x}/y"
    with pytest.raises(study.ConfigError, match=rf"config key '{key}': 'out{{x}}/y' holds a brace"):
        study.validate_config(config)
    config[key] = "any 'path' \"é\" $(x); `y` & | < > * ? [ ] ~ #\\ \n too"
    study.validate_config(config)


def snakemake_in(repo, workdir, configfile, *args, targets=()):
    """snakemake() with the workflow of the checkout `repo`."""
    cmd = command(workdir, configfile, *args, targets=targets)
    cmd[cmd.index("--snakefile") + 1] = str(repo / "workflow" / "Snakefile")
    assert cmd[0] == SNAKEMAKE
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, f"{cmd} failed ({r.returncode}):\n{r.stderr[-4000:]}"
    return r


class TestInTheWorkflow:
    pytestmark = NEEDS_SNAKEMAKE_AND_ENGINE

    def test_the_smoke_study_runs_from_a_path_with_a_space_quotes_and_a_non_ascii_letter(self, tmp_path):
        repo = checkout(tmp_path / ODD)
        config = smoke_config()
        config.update(granudrag="build/granudrag", results="résults 'smoke' \"s\"", logs="lögs 'smoke'")
        workdir = repo / "study run"
        workdir.mkdir()
        configfile = write_config(repo / "smoke é.yaml", config)
        results = workdir / config["results"]
        targets = [f"{config['results']}/table.csv", f"{config['results']}/report/fits.json"]
        snakemake_in(repo, workdir, configfile, "--cores", "2", targets=targets)
        table = pd.read_csv(results / "table.csv")
        assert len(table) == 12 and table.drag.notna().all() and (table.drag > 0).all()
        assert json.loads((results / "report" / "fits.json").read_text())
        plan = study.plan(config)
        for key in plan.pulls:
            assert "drag =" in (workdir / config["logs"] / "pulls" / f"{key}.log").read_text()
        assert not (results / "table_problems.txt").read_text()

    def test_a_config_value_with_a_semicolon_and_command_substitution_runs_nothing(self, tmp_path):
        marks = [tmp_path / name for name in ("p", "q", "r", "s")]
        config = smoke_config()
        config["results"] = f"out$(touch {marks[0]}); touch {marks[1]}; `touch {marks[2]}`"
        config["logs"] = f"logs; touch {marks[3]} #"
        workdir = tmp_path / "work"
        workdir.mkdir()
        configfile = write_config(workdir / "inject.yaml", config)
        # The restitution runs and the smallest bed (system II, 700 grains): shell rules.
        plan = study.plan(config)
        bed = min((k for k in plan.beds if k.startswith("system~II")), key=lambda k: (len(k), k))
        bed_out = study.bed_file(config["results"], bed)
        snakemake(workdir, configfile, "--cores", "2",
                  targets=[f"{config['results']}/restitution/engine.csv", bed_out])
        assert not [m.name for m in marks if m.exists()], "a config value ran a command"
        assert (workdir / config["results"] / "restitution" / "engine.csv").is_file()
        assert (workdir / bed_out).is_file()
        assert "bed:" in (workdir / config["logs"] / "beds" / f"{bed}.log").read_text()
        assert (workdir / config["logs"] / "restitution.log").is_file()

    def test_a_brace_path_is_refused_by_the_workflow_naming_the_key(self, tmp_path):
        config = dict(smoke_config(), results="out{x}")
        r = snakemake(tmp_path, write_config(tmp_path / "braces.yaml", config), "--dry-run", check=False)
        assert r.returncode != 0
        assert "config key 'results': 'out{x}' holds a brace" in r.stdout + r.stderr


def test_the_rules_spell_job_paths_through_the_one_declaration():
    # Outputs, benchmarks and logs of the simulation jobs come from paths.job_file, benchmark_file
    # and log_file: no rule spells a job's folder or file by hand.
    assert study.job_file("r", "pulls", "B/Fr~1") == study.run_file("r", "B/Fr~1") == "r/pulls/B/Fr~1/run.h5"
    assert study.benchmark_file("r", "beds", "B") == "r/benchmarks/beds/B.tsv"
    assert study.log_file("l", "columns", "C") == "l/columns/C.log"
    with pytest.raises(study.ConfigError, match="not a kind of job: 'pull'"):
        study.job_name("pull", "B")
    rules = (ROOT / "workflow" / "rules" / "simulate.smk").read_text()
    spelled = re.findall(r"/(?:beds|columns|pulls|benchmarks)/|\b(?:bed|column|run)\.h5\b|\.tsv\b", rules)
    assert not spelled, spelled
