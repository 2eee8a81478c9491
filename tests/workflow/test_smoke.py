"""The whole workflow end to end on config/smoke.yaml, in a temporary directory.

Checks the report, figures and table, that a finished study has nothing left to
do, that adding a grid value re-runs only the new pulls (beds reused), and that
a bad config names the bad key. About a minute on 2 cores.

The engine: $GRANUDRAG if set, else build/granudrag (tools/test.sh builds it). The Snakemake:
$GRANUDRAG_SNAKEMAKE if set (tools/test.sh runs this file with the project environment's
Snakemake 9, .venv/bin/snakemake, and with Debian's 7.21), else Debian's /usr/bin/snakemake.
"""
import json
import os
import re
import shutil
import subprocess
import zipfile

import pandas as pd
import pytest
import yaml
from workflow_support import (
    BINARY,
    NEEDS_SNAKEMAKE_AND_ENGINE,
    ROOT,
    SNAKEMAKE,
    job_counts,
    snakemake,
    snakemake_major,
    write_config,
)

import granudrag_study as study

pytestmark = NEEDS_SNAKEMAKE_AND_ENGINE

FIGURES = ["fig02_restitution", "fig04_force_trace", "fig05_drag_vs_Fr_mu0.5", "fig06_theta_vs_Fr",
           "fig07_coordination_distribution", "fig08_kappa_vs_Fr", "fig09_flow_field",
           "fig12_yield_vs_mu", "fig16_drag_vs_Fr_depth", "fig17_yield_vs_h", "fig20_kn_gamman"]

# The fixture `smoke` (the study run once, conftest.py) is shared with test_faults.py.


def test_report_and_figures(smoke):
    workdir, _, config = smoke
    report = workdir / config["results"] / "report"
    md = (report / "report.md").read_text()
    assert (report / "report.html").is_file() and (report / "fits.json").is_file()
    for name in FIGURES:
        assert (report / f"{name}.png").is_file(), name
        assert (report / f"{name}.pdf").is_file(), name
        assert f"]({name}.png)" in md, name


def test_table_has_one_row_per_planned_pull(smoke):
    workdir, _, config = smoke
    plan = study.plan(config)
    runs = pd.read_csv(workdir / config["results"] / "runs.csv", dtype={"system": str, "run": str})
    assert len(runs) == len(plan.pulls) == 13
    assert set(runs.run) == {f"pulls/{key}" for key in plan.pulls}
    # The kn sweep's point has two beds (seeds 1, 2): one row of the point table, combined.
    df = pd.read_csv(workdir / config["results"] / "table.csv", dtype={"system": str, "run": str})
    assert len(df) == 12
    two = df[df.n_beds == 2]
    assert len(two) == 1 and two.kn.iloc[0] == 5e4
    pair = runs[runs.kn == 5e4].drag.to_numpy()
    assert two.drag.iloc[0] == pytest.approx(pair.mean())
    assert two.drag_err.iloc[0] >= abs(pair[0] - pair[1]) / 2 * (1 - 1e-9)   # sqrt(s^2/2) at least
    assert df.drag.notna().all() and (df.drag > 0).all()
    assert set(df.system) == {"I", "II"}
    assert sorted(df[df.V == 0.01].h_requested.tolist()) == [3, 4, 5]
    assert ((df.h - df.h_requested).abs() < 2.0).all()
    assert not (workdir / config["results"] / "table_problems.txt").read_text()


def test_every_simulation_has_log_and_benchmark(smoke):
    workdir, _, config = smoke
    plan = study.plan(config)
    logs, results = workdir / config["logs"], workdir / config["results"]
    for key in plan.beds:
        assert "bed:" in (logs / "beds" / f"{key}.log").read_text()
        assert (results / "benchmarks" / "beds" / f"{key}.tsv").is_file()
    for key in plan.pulls:
        assert "drag =" in (logs / "pulls" / f"{key}.log").read_text()
        assert (results / "benchmarks" / "pulls" / f"{key}.tsv").is_file()


# The movie's frames here: fewer than movie.frames' default (120), as rendering each one is most
# of the target's time; the count asked for is still the count checked.
MOVIE_FRAMES = 24


def test_the_movie_target_pulls_figure_4s_pull_again_with_frames(smoke):
    import h5py

    workdir, _, config = smoke
    config = dict(config, movie={"frames": MOVIE_FRAMES})
    configfile = write_config(workdir / "movie.yaml", config)
    snakemake(workdir, configfile, "--cores", "2", "movie")
    results = workdir / config["results"]
    movie = results / "report" / "movie.mp4"
    assert movie.is_file() and movie.stat().st_size > 10_000
    trace = study.trace_pull(study.plan(config))
    with h5py.File(results / "movie" / "run.h5") as f, h5py.File(study.run_file(str(results), trace.key)) as g:
        frames = f["particles/frames/position/value"].shape[0]
        assert abs(frames - MOVIE_FRAMES) <= 2  # movie.frames, up to the rounding of the interval to steps
        # Frames are output only: the same pull gives the same drag, bit for bit.
        assert f["observables/drag"].attrs["value"] == g["observables/drag"].attrs["value"]
    assert (results / "movie" / "run.h5.xdmf").read_text().count("<Time Value") == frames


def test_finished_study_has_nothing_to_do(smoke):
    workdir, configfile, _ = smoke
    r = snakemake(workdir, configfile, "--dry-run")
    assert "Nothing to be done" in r.stdout + r.stderr


def caption_start(name):
    """The first words of a figure's caption (workflow/report/NAME.rst) up to any markup."""
    first = (ROOT / "workflow" / "report" / f"{name}.rst").read_text().splitlines()[0]
    return re.split(r"[`*_|\\]", first)[0].strip()


def test_snakemake_report_has_every_figure_and_caption(smoke, tmp_path):
    """Snakemake's own --report (the report: directive), written with no network."""
    workdir, configfile, _ = smoke
    if snakemake_major() >= 8:
        # A self-contained zip (the page's scripts are in Snakemake's package), written here
        # in a network namespace of its own: no network at all.
        out = tmp_path / "report.zip"
        cmd = ["unshare", "--net", SNAKEMAKE, "--snakefile", str(ROOT / "workflow" / "Snakefile"),
               "--directory", str(workdir), "--configfile", str(configfile), "--report", str(out)]
        if os.geteuid() != 0:
            cmd = cmd[2:]  # a network namespace needs root; then the same report with network
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-3000:]
        with zipfile.ZipFile(out) as z:
            names = z.namelist()
            html = z.read(next(n for n in names if n.endswith("/report.html") and "/data/" not in n)).decode()
        for name in FIGURES:
            assert any(n.endswith(f"/{name}.png") for n in names), name
    else:
        # 7.21 would download its page assets; offline_report.py runs the same report without
        # them.
        out = workdir / "snakemake_report.html"
        cmd = ["/usr/bin/python3", str(ROOT / "workflow" / "scripts" / "offline_report.py"),
               "--snakefile", str(ROOT / "workflow" / "Snakefile"), "--directory", str(workdir),
               "--configfile", str(configfile), "--report", str(out)]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-3000:]
        html = out.read_text()
        for name in FIGURES:
            assert f"{name}.png" in html, name
    for name in FIGURES:
        # The caption, as text or as the JSON string the report's page holds.
        start = caption_start(name)
        assert len(start) > 10 and (start in html or json.dumps(start)[1:-1] in html), name


def test_one_figure_reruns_alone(smoke):
    """Redrawing one figure family re-runs its rule and the report's assembly, not the fits
    (their bootstraps) nor the other figures."""
    workdir, configfile, _ = smoke
    r = snakemake(workdir, configfile, "--dry-run", "--quiet", "rules", "--forcerun", "figures_yield")
    assert job_counts(r.stdout + r.stderr) == {"figures_yield": 1, "report": 1, "all": 1}


def test_rerun_triggers(smoke):
    """As the README says: a changed rule parameter (here report.n_boot, a param of the fits
    rule) re-runs that rule and what follows; with --rerun-triggers mtime only newer input
    files count, so nothing is re-run."""
    workdir, _, config = smoke
    changed = yaml.safe_load(yaml.safe_dump(config))
    changed["report"]["n_boot"] = config["report"]["n_boot"] + 1
    configfile = write_config(workdir / "n_boot.yaml", changed)
    dry = snakemake(workdir, configfile, "--dry-run", "--quiet", "rules")
    counts = job_counts(dry.stdout + dry.stderr)
    assert counts.get("fits") == 1 and "pull" not in counts and "bed" not in counts, counts
    r = snakemake(workdir, configfile, "--dry-run", "--rerun-triggers", "mtime")
    assert "Nothing to be done" in r.stdout + r.stderr


def test_figure_without_data_is_a_note_in_the_report(smoke):
    # The smoke study has one yield pull per D at a single mu: no phi_mu fit, no Fig. 14.
    from analysis.figures.figures import not_drawn_reason

    workdir, _, config = smoke
    report = workdir / config["results"] / "report"
    why = not_drawn_reason(report / "fig14_phi_vs_mu.png")
    assert why and f"Fig. 14: φ_μ vs μ: not drawn — {why}." in (report / "report.md").read_text()
    assert not_drawn_reason(report / "fig12_yield_vs_mu.png") is None


def test_bad_config_names_the_key(smoke, tmp_path):
    _, _, config = smoke
    bad = dict(config, sweeps=[dict(config["sweeps"][0], D="two")] + config["sweeps"][1:])
    r = snakemake(tmp_path, write_config(tmp_path / "bad.yaml", bad), "--dry-run", check=False)
    assert r.returncode != 0
    assert "sweeps[0].D" in r.stdout + r.stderr


def test_extending_a_grid_reruns_only_the_new_pulls(smoke):
    workdir, _, config = smoke
    results = workdir / config["results"]
    beds = {p: p.stat().st_mtime_ns for p in (results / "beds").rglob("bed.h5")}
    runs = {p: p.stat().st_mtime_ns for p in (results / "pulls").rglob("run.h5")}
    extended = yaml.safe_load(yaml.safe_dump(config))
    extended["sweeps"][0]["Fr"] = extended["sweeps"][0]["Fr"] + [3]      # drag: D = 1.5, 2
    configfile = write_config(workdir / "extended.yaml", extended)

    dry = snakemake(workdir, configfile, "--dry-run", "--quiet", "rules")
    counts = job_counts(dry.stdout + dry.stderr)
    assert counts.get("pull") == 2, counts
    assert "bed" not in counts, counts
    # flow_field: a new pull may be nearer to a Fig. 9 panel's (D, V) than the old choice.
    analysis = {"table", "flow_field", "fits", "report", "all"} | {r for r in counts if r.startswith("figure")}
    assert set(counts) <= {"pull"} | analysis, counts
    # The same without Snakemake's metadata on input lists (as for a results directory copied
    # elsewhere): the plan's file, rewritten by the dry run above, makes the table out of date.
    mtime_only = snakemake(workdir, configfile, "--dry-run", "--quiet", "rules", "--rerun-triggers", "mtime")
    counts = job_counts(mtime_only.stdout + mtime_only.stderr)
    assert counts.get("pull") == 2 and counts.get("table") == 1 and "bed" not in counts, counts

    # Run to the table only: what is checked below (the figures, fits and report that follow it are
    # planned above; the smoke study makes them).
    snakemake(workdir, configfile, "--cores", "2", targets=[f"{config['results']}/table.csv"])
    assert {p: p.stat().st_mtime_ns for p in (results / "beds").rglob("bed.h5")} == beds
    assert all(p.stat().st_mtime_ns == t for p, t in runs.items())
    new = set((results / "pulls").rglob("run.h5")) - set(runs)
    assert sorted(p.parent.name for p in new) == ["Fr~3", "Fr~3"]
    df = pd.read_csv(results / "table.csv")
    assert len(df) == 14


@pytest.mark.skipif(shutil.which("sbatch") is None, reason="no SLURM client")
def test_slurm_profile_parses(smoke):
    """The SLURM profile of this Snakemake generation (slurm: the executor plugin, Snakemake >= 8;
    slurm-v7: sbatch from the cluster: line) is read and the jobs it would submit are listed
    (no cluster needed)."""
    workdir, configfile, _ = smoke
    profile = "slurm" if snakemake_major() >= 8 else "slurm-v7"
    r = snakemake(workdir, configfile, "--profile", str(ROOT / "workflow" / "profiles" / profile),
                  "--dry-run", "--forcerun", "pull")
    assert "pull" in job_counts(r.stdout + r.stderr)


def test_test_directory_holds_the_smoke_config(tmp_path):
    """The catalog's convention: `--directory .test` runs .test/config/config.yaml, without
    --configfile; config/smoke.yaml is that file."""
    assert (ROOT / "config" / "smoke.yaml").resolve() == (ROOT / ".test" / "config" / "config.yaml").resolve()
    shutil.copytree(ROOT / ".test", tmp_path / ".test")
    cmd = [SNAKEMAKE, "--snakefile", str(ROOT / "workflow" / "Snakefile"), "--directory", str(tmp_path / ".test"),
           "--dry-run", "--quiet", "rules", "--config", f"granudrag={BINARY}"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    counts = job_counts(r.stdout + r.stderr)
    assert (counts.get("bed"), counts.get("pull")) == (6, 13), counts


@pytest.mark.parametrize("name", ["smoke.yaml", "config.yaml", "paper.yaml"])
def test_lint_is_clean(name, tmp_path):
    """`snakemake --lint` finds nothing to improve (it exits non-zero when it does)."""
    r = snakemake(tmp_path, ROOT / "config" / name, "--lint", "json", check=False)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
