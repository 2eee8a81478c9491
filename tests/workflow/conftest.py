"""The smoke study, run once per test session and shared by test_smoke.py and test_faults.py."""
import shutil

import pytest
from workflow_support import smoke_config, snakemake, write_config


@pytest.fixture(scope="session")
def smoke(tmp_path_factory):
    """config/smoke.yaml run end to end (--cores 2) in a temporary directory: (workdir,
    configfile, config). Its runs.csv, table.csv and report/fits.json as this uninterrupted run
    left them are copied to workdir/uninterrupted/ before any test changes the study
    (test_smoke.py extends a grid)."""
    workdir = tmp_path_factory.mktemp("smoke")
    config = smoke_config()
    configfile = write_config(workdir / "smoke.yaml", config)
    snakemake(workdir, configfile, "--cores", "2")
    keep = workdir / "uninterrupted"
    keep.mkdir()
    results = workdir / config["results"]
    shutil.copy2(results / "runs.csv", keep / "runs.csv")
    shutil.copy2(results / "table.csv", keep / "table.csv")
    shutil.copy2(results / "report" / "fits.json", keep / "fits.json")
    return workdir, configfile, config
