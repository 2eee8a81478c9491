"""The `validation` target: a validation config's runs, compared with the reference protocol."""
import yaml
from test_smoke import BINARY, ROOT, job_counts, pytestmark, snakemake, write_config  # noqa: F401


def tiny(name):
    """config/validate/<name>.yaml on a tiny bed, short pulls: the whole DAG in seconds."""
    with open(ROOT / "config" / "validate" / f"{name}.yaml") as fh:
        config = yaml.safe_load(fh)
    config["granudrag"] = str(BINARY)
    return config


def test_every_validation_config_plans_its_comparison(tmp_path):
    for name in ("yield_speed", "box_size", "stiffness"):
        r = snakemake(tmp_path / name, write_config(tmp_path / f"{name}.yaml", tiny(name)), "-n", "validation")
        counts = job_counts(r.stdout)
        assert counts.get("validation") == 1 and counts.get("table") == 1, (name, counts)
        assert counts["pull"] == 24 and "report" not in counts, (name, counts)


def test_yield_speed_validation_runs_end_to_end(tmp_path):
    config = tiny("yield_speed")
    config["systems"]["I"].update(lx=8, ly=8, grains=700, pour={"ke_threshold": 1e-5, "max_settle_time": 20})
    config["sweeps"][0].update(D=2, mu=0.5, depth=3, V=[0.05, 0.1], pull={"distance": 0.3, "transient": 0.1})
    r = snakemake(tmp_path, write_config(tmp_path / "c.yaml", config), "--cores", "2", "validation")
    out = tmp_path / config["results"]
    md = (out / "validate_yield_speed.md").read_text()
    assert "V = 0.1 against 0.05" in md and ("instead of 0.05" in md or "keep it" in md), md
    assert (out / "validate_yield_speed.png").stat().st_size > 5000
    assert len((out / "validate_yield_speed.csv").read_text().splitlines()) == 2   # one point, one variant
    assert r.returncode == 0
