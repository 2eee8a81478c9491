"""Paths that reach a shell (issue 76): the rules quote every path and argument.

- The smoke study, to its table and fits, from a checkout whose path holds a space, quotes and a
  non-ASCII letter, with results and logs directories named likewise.
- A config whose paths hold `;`, `$(...)` and backquotes runs nothing of them: a pour, the
  restitution curve and their logs land under those names, literally.
- A path with braces (Snakemake's wildcards) is refused by the config check, naming the key.

Under Snakemake 9 and 7.21 alike (GRANUDRAG_SNAKEMAKE, workflow_support.py).
"""
import json
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
