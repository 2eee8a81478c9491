"""analysis.ladder.ladder: a rung collected from a study's results, the claims-by-rungs table with the
report's verdicts, the κ shell slopes and the Fr_2-range refits, and the `ladder` CLI."""
import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import synth
from test_runs import write_run

from analysis.core.table import combine_beds, load_csv, save_csv
from analysis.fits.fitset import load_results, run_fits, save_results
from analysis.ladder.ladder import (
    CLAIMS_BEGIN,
    CLAIMS_END,
    LADDER_BEGIN,
    LADDER_END,
    NOT_RUN,
    SHELL_COLUMNS,
    LadderError,
    collect,
    rung_claims,
    write_ladder,
)
from analysis.report.report import comparisons

ROOT = Path(synth.__file__).resolve().parents[2]
FR = np.array([0.2, 0.4, 0.6, 0.8, 1.5, 2, 3, 4, 5.5, 6.5, 8, 10, 12, 15])
WIDTHS = np.array([0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0])
KAPPA_SLOPE = "κ(Fr) slope (Fig. 8)"


def point_table(kappa=(0.887, 0.185), seed=0, Ds=(2, 3), seeds=(1, 2), noise=0.02):
    """A rung's table.csv: system I, μ = 0.5, a drag obeying the three-regime law with Fr_1 = 1
    and Fr_2 = 5 (synth), κ = k0 + k1 Fr, θ of Eq. 7, replicate beds combined as the workflow does."""
    rng = np.random.default_rng(seed)
    rows = []
    for D in Ds:
        for s in seeds:
            for fr in FR:
                F = synth.drag_true(D, 14.0, 0.5, fr) * (1 + noise * rng.standard_normal())
                k = kappa[0] + kappa[1] * fr + 0.01 * rng.standard_normal()
                n = 0.5 * (D + 1.0) ** 2 / (1.0 + 0.2 * fr)
                rows.append(dict(system="I", D=float(D), h=14.0, mu=0.5, kn=2e5, gamman=792.4466,
                                 V=float(synth.speed_for(fr, D)), Fr=float(fr), drag=F, drag_err=noise * F,
                                 n_contacts=n, theta=-0.15 * fr ** 0.38 + np.pi / 2.45
                                 + 0.005 * rng.standard_normal(), theta_err=0.005,
                                 Z=k * n * 2 * np.sqrt(3) / (D + 1.0) ** 2, kappa=k, kappa_err=0.01,
                                 run=f"pulls/system~I/D~{D}/mu~0.5/seed~{s}/Fr~{fr:g}", seed=float(s),
                                 plateau=True, drag_dof=20.0))
    return combine_beds(pd.DataFrame(rows))


SHELL_SLOPES = ((1.0, 0.2), (3.0, 0.05))     # (width, slope of κ(Fr)) of shell_table


def shell_table(slopes=SHELL_SLOPES, seed=0, noise=0.02):
    """kappa_shells.csv rows: κ = 0.9 + slope(w) Fr + noise per run, D = 2 and 3, three beds;
    plus μ = 0 runs, which the κ(Fr) of Fig. 8 (μ = 0.5) leaves out."""
    rng = np.random.default_rng(seed)
    rows = []
    for mu in (0.5, 0.0):
        for D in (2.0, 3.0):
            for s in (1.0, 2.0, 3.0):
                for fr in (0.5, 1, 2, 3, 4, 5, 6, 8, 10, 12):
                    bed = 0.01 * rng.standard_normal()       # a bed shifts all its shells alike
                    for w, k1 in slopes:
                        rows.append(dict(system="I", D=D, h=14.0, mu=mu, kn=2e5, Fr=float(fr),
                                         V=float(synth.speed_for(fr, D)), seed=s, n_contacts=5.0, width=w,
                                         Z=4.0, kappa=0.9 + k1 * fr + bed + noise * rng.standard_normal(),
                                         gamman=792.4466, ring_grains=100.0, run=f"D~{D:g}/seed~{s:g}/Fr~{fr:g}",
                                         lx=20.0, ly=20.0))
    return pd.DataFrame(rows)[SHELL_COLUMNS]


# --- collect ---------------------------------------------------------------

BED = "system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.05359/seed~1"
BENCH_HEAD = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def add_shells(path, kappa):
    with h5py.File(path, "a") as f:
        g = f.create_group("observables/bulk_coordination/shells")
        g["width"], g["Z"], g["kappa"] = WIDTHS, 3.0 + 0.1 * WIDTHS, kappa
        g["grains"] = np.arange(len(WIDTHS), dtype=np.int64) * 10


@pytest.fixture
def study(tmp_path):
    """A study's results directory as the workflow leaves it, and its config."""
    res = tmp_path / "results" / "ladder" / "rung1"
    (res / "report").mkdir(parents=True)
    save_csv(point_table(), res / "table.csv")
    (res / "runs.csv").write_text("system,D\nI,2\n")
    (res / "report" / "fits.json").write_text('{"format": "granudrag-fits"}\n')
    (res / "report" / "report.md").write_text("# report\n")
    bench = res / "benchmarks" / "pulls" / BED
    bench.mkdir(parents=True)
    (bench / "Fr~1.tsv").write_text(BENCH_HEAD + "3.09\t0:00:03\t25.6\t40.6\t12.6\t17.2\t0.00\t8.92\t80.25\t2.96\n")
    (bench / "Fr~2.tsv").write_text(BENCH_HEAD + "10.0\t0:00:10\tNA\tNA\tNA\tNA\tNA\tNA\tNA\tNA\n")
    (res / "benchmarks" / "beds").mkdir()
    (res / "benchmarks" / "beds" / "b.tsv").write_text(BENCH_HEAD + "6.0\t0:00:06\t1\t1\t1\t1\t0\t0\t90\t5.0\n")
    pulls = res / "pulls" / BED
    add_shells(write_run(pulls / "Fr~1" / "run.h5", speed=0.75), kappa=0.9 + 0.01 * WIDTHS)
    add_shells(write_run(pulls / "Fr~2" / "run.h5", speed=1.5), kappa=1.1 + 0.01 * WIDTHS)
    write_run(pulls / "Fr~0.5" / "run.h5", speed=0.375)              # before the engine recorded shells
    (pulls / "Fr~3").mkdir()
    (pulls / "Fr~3" / "run.h5").write_text("not hdf5")                # unusable: left out, counted
    config = tmp_path / "config" / "rung1.yaml"
    config.parent.mkdir()
    config.write_text(f"results: {res}\nthreads: 1\n")
    return config, res


def test_collect_copies_the_files_and_counts_the_cost(study, tmp_path):
    config, res = study
    out = tmp_path / "reproduction" / "rung1"
    info = collect(config, res, out, wall_seconds=1234.5, cores=2, started="2026-11-25T10:00:00")
    for name, src in (("config.yaml", config), ("table.csv", res / "table.csv"), ("runs.csv", res / "runs.csv"),
                      ("fits.json", res / "report" / "fits.json"), ("report.md", res / "report" / "report.md")):
        assert (out / name).read_bytes() == src.read_bytes(), name
    doc = json.loads((out / "run.json").read_text())
    assert doc == info
    assert doc["rung"] == "rung1" and doc["config"] == str(config) and doc["cores"] == 2
    assert doc["wall_seconds"] == 1234.5 and doc["started"] == "2026-11-25T10:00:00"
    # cpu_time where the benchmark has it (2.96 + 5.0 s), wall seconds x 1 thread where it is NA (10 s).
    assert doc["core_hours"] == pytest.approx((2.96 + 5.0 + 10.0) / 3600)
    assert doc["jobs"] == 3 and "cpu_time" in doc["core_hours_from"] and "s × 1 thread" in doc["core_hours_from"]
    assert {"cpu", "cores", "memory_gib"} <= set(doc["machine"]) and doc["commit"] and doc["date"]
    shells = pd.read_csv(out / "kappa_shells.csv")
    assert list(shells.columns) == SHELL_COLUMNS
    assert len(shells) == 2 * len(WIDTHS)                             # two runs with shells, a row per width
    one = shells[np.isclose(shells.Fr, 1.0)].sort_values("width")
    np.testing.assert_allclose(one.width, WIDTHS)
    np.testing.assert_allclose(one.kappa, 0.9 + 0.01 * WIDTHS)
    assert (one.D == 2).all() and (one.seed == 1).all() and (one.mu == 0.5).all() and (one.system == "I").all()
    notes = " ".join(doc["notes"])
    assert "1 of 4 runs have no" in notes and "1 unusable run files" in notes
    assert not list(out.glob("*.tmp"))


def test_collect_names_the_missing_file_and_the_fix(study, tmp_path):
    config, res = study
    (res / "report" / "fits.json").unlink()
    with pytest.raises(LadderError, match=r"fits\.json: no such file \(run the study first: tools/study\.sh"):
        collect(config, res, tmp_path / "out", wall_seconds=1, cores=1)
    assert not (tmp_path / "out" / "run.json").exists()


def test_collect_without_shells_writes_a_header_only(study, tmp_path):
    config, res = study
    import shutil
    shutil.rmtree(res / "pulls")
    info = collect(config, res, tmp_path / "out", wall_seconds=1, cores=1)
    assert pd.read_csv(tmp_path / "out" / "kappa_shells.csv").empty
    assert any("header only" in n for n in info["notes"])


@pytest.mark.slow
def test_collect_from_the_command_line_defaults_to_results_reproduction(study, tmp_path):
    config, res = study
    r = subprocess.run([sys.executable, "-m", "analysis", "ladder", "collect", "--config", str(config),
                        "--results", str(res), "--wall-seconds", "60", "--cores", "2"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "results" / "reproduction" / "rung1" / "run.json").read_text())["cores"] == 2


# --- the ladder --------------------------------------------------------------

def make_rung(root, name, kappa, seed):
    """A collected rung: the files `collect` writes, fitted from a synthetic table."""
    d = root / name
    d.mkdir(parents=True)
    df = point_table(kappa=kappa, seed=seed)
    save_csv(df, d / "table.csv")
    save_results(d / "fits.json", run_fits(df, n_boot=20, seed=0))
    shell_table(seed=seed).to_csv(d / "kappa_shells.csv", index=False)
    (d / "run.json").write_text(json.dumps({
        "rung": name, "config": f"config/ladder/{name}.yaml", "wall_seconds": 3725.0, "cores": 2,
        "started": "2026-11-25T10:00:00", "core_hours": 1.5, "core_hours_from": "cpu_time", "jobs": 56,
        "machine": {"cpu": "Test CPU", "cores": 2, "memory_gib": 7.7}, "commit": "abc1234",
        "date": "2026-11-25T12:00:00+00:00", "notes": []}))
    return d


README = f"# The ladder\n\nintro\n\n{LADDER_BEGIN}\nold table\n{LADDER_END}\n\ntail\n"


@pytest.fixture(scope="module")
def ladder_root(tmp_path_factory):
    """Rung A reproduces κ(Fr) (the paper's line), rung B does not (κ falling with Fr), rung C is
    listed but not run."""
    root = tmp_path_factory.mktemp("reproduction")
    (root / "ladder.yaml").write_text(
        "rungs:\n  - {name: rung-a, label: 'K_n 2e5'}\n  - {name: rung-b, label: 'K_n 2e6'}\n"
        "  - {name: rung-c, label: 'K_n 2e7'}\nclaims:\n  c: 'kappa line'\n")
    make_rung(root, "rung-a", (0.887, 0.185), seed=1)
    make_rung(root, "rung-b", (0.948, -0.020), seed=2)
    (root / "README.md").write_text(README)
    written = write_ladder(root, n_boot=10, seed=0)
    return root, written


@pytest.mark.slow
def test_ladder_csv_has_the_reports_verdicts(ladder_root):
    root, _ = ladder_root
    t = pd.read_csv(root / "ladder.csv")
    slope = t[t.quantity == KAPPA_SLOPE].set_index("rung")
    assert slope.loc["rung-a", "verdict"] == "reproduced within error bars"
    assert slope.loc["rung-b", "verdict"] == "not reproduced"
    assert slope.loc["rung-c", "verdict"] == NOT_RUN and np.isnan(slope.loc["rung-c", "value"])
    assert slope.loc["rung-a", "value"] == pytest.approx(0.185, abs=0.01)
    assert slope.loc["rung-a", "core_hours"] == 1.5 and slope.loc["rung-a", "machine_cpu"] == "Test CPU"
    assert (t[t.rung == "rung-c"].verdict == NOT_RUN).all()
    assert {"a", "b", "c"} <= set(t.claim) and set(t.claim) <= set("abcdefg")
    # Exactly the report's verdicts, in its order.
    for name in ("rung-a", "rung-b"):
        d = root / name
        report = comparisons(load_results(d / "fits.json"), load_csv(d / "table.csv"))
        claims = rung_claims(d)
        assert [c["verdict"] for c in claims] == [r.verdict for r in report]
        assert [c["report_quantity"] for c in claims] == [r.quantity for r in report]


def test_ladder_md_and_readme_section(ladder_root):
    root, written = ladder_root
    md = (root / "ladder.md").read_text()
    assert "| 3 | rung-c | K_n 2e7 | — | not run |" in md
    assert "1:02:05 on 2 cores" in md and "abc1234" in md
    assert "### (c) kappa line" in md and "### (a) three regimes" in md
    top = [line for line in md.splitlines() if line.startswith(f"| c | {KAPPA_SLOPE} |")]
    assert len(top) == 1 and "| rung-b |" in top[0] and top[0].endswith("| not reproduced |")
    readme = (root / "README.md").read_text()
    assert "old table" not in readme and md.strip() in readme
    assert readme.startswith("# The ladder\n\nintro\n") and readme.endswith(f"{LADDER_END}\n\ntail\n")
    for name in ("claim_a.png", "claim_b.png", "claim_c.png", "kappa_shells.png", "fr2_range.png"):
        assert (root / name).stat().st_size > 1000 and root / name in written, name
    assert not (root / "claim_d.png").exists()              # no φ_0 in these rungs: no figure
    assert not list(root.glob("*.tmp"))
    slopes = pd.read_csv(root / "kappa_shells.csv")
    assert set(slopes.rung) == {"rung-a", "rung-b"} and {"all", "2", "3"} == set(slopes.D.astype(str))
    knee = pd.read_csv(root / "knee_fr5.csv")
    assert len(knee) == 4 and set(knee.rung) == {"rung-a", "rung-b"} and (knee.z > 2).all()
    assert "### The drag's slope above Fr 5 against below" in md


SUMMARY = """summary:
  a:
    closest: [rung-b, rung-a]
    show: {"Fr_2 (μ = 0.5, D = 3)": Fr₂}
    reading: a crossover near 5
    differs: K_n
    next: rung-c, 1 core-hour
  c:
    closest: [rung-a]
    show: {"κ(Fr) slope (Fig. 8)": κ slope, "κ(Fr) intercept (Fig. 8)": κ intercept}
    reading: the paper's line
    differs: the box
    next: none
    deep:
      rung: rung-a
      show: {sum_yield: "μ = 0.5, α from F_Y", shallow_drag: shallow drag}
    beside:
      - {rung: rung-b, show: {"κ(Fr) slope (Fig. 8)": κ slope elsewhere}}
      - {rung: rung-c, show: {"κ(Fr) slope (Fig. 8)": κ slope not run}}
"""


def deep_law_csv(path):
    """A deep_law.csv as analysis.deep_law writes it: a sum rule on the deep depths, a shallow test."""
    rows = [dict(D=4, mu=0.5, kn=2e4, gamman=199.05, quantity="sum_yield", depths="h >= 45", h_lo=45.03,
                 h_hi=64.96, n=3, value=2.8016, err=0.28599, chi2=np.nan, dof=2.76, p=np.nan,
                 verdict="reproduced within error bars", note="alpha + phi"),
            dict(D=4, mu=0.5, kn=2e4, gamman=199.05, quantity="shallow_drag", depths="h < 45", h_lo=10.02,
                 h_hi=40.3, n=15, value=np.nan, err=np.nan, chi2=51.8, dof=15, p=6.1e-6,
                 verdict="leaves the deep law", note="departures")]
    pd.DataFrame(rows).to_csv(path, index=False)


@pytest.mark.slow
def test_the_claim_table_quotes_the_rung_closest_to_the_papers_conditions(tmp_path):
    # Rung A reproduces κ(Fr), rung B (listed last) does not. ladder.yaml calls rung A the closest
    # to the paper's conditions for (c), rung B for (a): each claim's row, its figure and the
    # "Verdict at the top rung" follow that, not the order of the list.
    (tmp_path / "ladder.yaml").write_text(
        "rungs:\n  - {name: rung-a, label: 'K_n 2e5'}\n  - {name: rung-b, label: 'K_n 2e6'}\n"
        "  - {name: rung-c, label: 'K_n 2e7'}\nclaims:\n  c: 'kappa line'\n" + SUMMARY)
    make_rung(tmp_path, "rung-a", (0.887, 0.185), seed=1)
    make_rung(tmp_path, "rung-b", (0.948, -0.020), seed=2)
    deep_law_csv(tmp_path / "rung-a" / "deep_law.csv")
    readme = f"# The ladder\n\n{CLAIMS_BEGIN}\nold claims\n{CLAIMS_END}\n\n{LADDER_BEGIN}\nold\n{LADDER_END}\n"
    (tmp_path / "README.md").write_text(readme)
    (tmp_path / "evidence_g.png").write_bytes(b"stale")
    written = write_ladder(tmp_path, n_boot=10, seed=0)
    claims = (tmp_path / "claims.md").read_text()
    rows = {line.split(" | ")[0]: line for line in claims.splitlines() if line.startswith("| **(")}
    assert list(rows) == ["| **(a)** three regimes, Fr_1 ≈ 1 and Fr_2 ≈ 5, independent of D and h",
                          "| **(c)** kappa line"]
    a, c = rows.values()
    assert "| `rung-b` | Fr₂: " in a and "(paper ≈ 5) — " in a
    assert "| a crossover near 5 | K_n | rung-c, 1 core-hour |" in a
    assert "the slope past Fr 5 over the slope below (D = 3, Fr 1–10): " in a
    assert "| `rung-a` | κ slope: " in c and "(paper 0.185) — reproduced within error bars<br>κ intercept: " in c
    # (c)'s `beside` entry quotes rung-b's κ slope, named, after the top rung's cells; rung-c has
    # not run, so it adds nothing.
    elsewhere = c.split("<br>κ slope elsewhere, `rung-b`: ")
    assert len(elsewhere) == 2 and "(paper 0.185) — not reproduced" in elsewhere[1].split("<br>")[0]
    assert "κ slope not run" not in c
    # (c)'s `deep` entry adds the depth law's verdicts, each with the depths it holds for.
    assert ("<br>μ = 0.5, α from F_Y, h ≥ 45 d (45-65 d), `rung-a`: 2.80 ± 0.29 (paper ≈ 3) — reproduced within "
            "error bars<br>shallow drag, h < 45 d (10-40.3 d), `rung-a`: p = 6.1e-06 — leaves the deep law |") in c
    assert '<a href="evidence_c.png"><img src="evidence_c.png" width="260" alt="claim (c) at rung-a"></a> |' in c
    for letter in "ac":
        png = tmp_path / f"evidence_{letter}.png"
        assert png.stat().st_size > 1000 and png in written
    assert not (tmp_path / "evidence_g.png").exists()         # no row for (g): a stale figure goes
    text = (tmp_path / "README.md").read_text()
    assert "old claims" not in text and claims.strip() in text and f"{LADDER_BEGIN}\nold\n" not in text
    top = [line for line in (tmp_path / "ladder.md").read_text().splitlines()
           if line.startswith(f"| c | {KAPPA_SLOPE} |")]
    assert len(top) == 1 and "| rung-a |" in top[0] and top[0].endswith("| reproduced within error bars |")
    # A rung the summary names must be listed.
    (tmp_path / "ladder.yaml").write_text("rungs: [{name: rung-a}]\nsummary: {c: {closest: [rung-z]}}\n")
    with pytest.raises(LadderError, match="summary.c.closest names rungs not listed: rung-z"):
        write_ladder(tmp_path, n_boot=5)
    for beside, message in (("[{rung: rung-z, show: {x: y}}]", r"summary.c.beside\[0\].rung names a rung not listed"),
                            ("{rung: rung-a, show: {x: y}}", "summary.c.beside takes a list of")):
        (tmp_path / "ladder.yaml").write_text(f"rungs: [{{name: rung-a}}]\nsummary: {{c: {{beside: {beside}}}}}\n")
        with pytest.raises(LadderError, match=message):
            write_ladder(tmp_path, n_boot=5)


def test_readme_without_markers_is_left_alone(tmp_path):
    (tmp_path / "ladder.yaml").write_text("rungs: [{name: later, label: not yet}]\n")
    (tmp_path / "README.md").write_text("# no markers\n")
    write_ladder(tmp_path, n_boot=5)
    assert (tmp_path / "README.md").read_text() == "# no markers\n"
    t = pd.read_csv(tmp_path / "ladder.csv")
    assert list(t.rung) == ["later"] and list(t.verdict) == [NOT_RUN]


def run(*args):
    return subprocess.run([sys.executable, "-m", "analysis", *map(str, args)], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)


@pytest.mark.slow
def test_cli_table_rewrites_the_same_files(ladder_root):
    root, _ = ladder_root
    names = ("ladder.csv", "ladder.md", "claim_c.png", "fr2_range.csv", "kappa_shells.png")
    before = {n: (root / n).read_bytes() for n in names}
    r = run("ladder", "table", root, "--n-boot", 10, "--seed", 0)
    assert r.returncode == 0, r.stderr
    assert {n: (root / n).read_bytes() for n in names} == before     # deterministic


@pytest.mark.slow
def test_cli_missing_root_names_it(tmp_path):
    missing = tmp_path / "nowhere"
    r = run("ladder", "table", missing)
    assert r.returncode == 2 and str(missing) in r.stderr and "Traceback" not in r.stderr
    (tmp_path / "ladder.yaml").write_text("rungs: []\n")
    r = run("ladder", "table", tmp_path)
    assert r.returncode == 2 and "ladder.yaml" in r.stderr and "Traceback" not in r.stderr


def test_depth_series_line_up_by_the_requested_depth(tmp_path):
    # The report names a system II series by its measured depth, the mean of its beds (9.46
    # with one bed, 9.42 with two): the ladder names it by the depth the config asked for, so
    # both rungs' rows are one quantity. Without h_requested the measured depth stays.
    import synth

    df = synth.make_table(seed=5, mus=(0.5,), kn_variants=False)
    rows = []
    for shift, name in ((0.04, "one-bed"), (-0.02, "two-beds")):
        t = df.copy()
        t["h_requested"] = t.h
        t.loc[t.system == "II", "h"] += shift
        d = tmp_path / name
        d.mkdir()
        save_csv(t, d / "table.csv")
        save_results(d / "fits.json", run_fits(t, n_boot=0, seed=0))
        rows.append({c["quantity"] for c in rung_claims(d) if "h =" in c["quantity"]})
    assert rows[0] and rows[0] == rows[1]
    assert all("requested h = " in q for q in rows[0])
    assert {f"requested h = {h:g})" for h in df[df.system == "II"].h.unique()} >= \
        {q[q.index("requested"):] for q in rows[0]}


@pytest.mark.slow
def test_a_recorded_rung_is_refitted_from_its_runs(tmp_path):
    # analysis.ladder_refit: table.csv from runs.csv (two beds a point), fits.json with the options
    # the rung recorded, report.md; a rung listed but not run is left alone.
    from analysis.ladder_refit import main

    root = tmp_path / "reproduction"
    d = root / "rung-a"
    d.mkdir(parents=True)
    (root / "ladder.yaml").write_text("rungs: [rung-a, rung-b]\n")
    one = synth.make_table(seed=3, mus=(0.0, 0.5), kn_variants=False)
    beds = []
    for b, k in ((1, 0.0), (2, 0.05)):       # the second bed's κ higher: a scatter κ's error must hold
        part = one.assign(seed=float(b), kappa=one.kappa + k, run=[f"{r}/seed~{b}/pull" for r in one.run])
        beds.append(part)
    save_csv(pd.concat(beds, ignore_index=True), d / "runs.csv")
    save_results(d / "fits.json", run_fits(one, n_boot=3, seed=4))
    (d / "run.json").write_text("{}")
    assert main([str(root)]) == 0
    table = load_csv(d / "table.csv")
    assert len(table) == len(one) and (table.n_beds == 2).all()
    assert np.allclose(table.kappa_err, 0.025)    # sqrt(max(s², W)/k), s² = 0.05²/2 above W = 0.01²
    doc = json.loads((d / "fits.json").read_text())
    assert doc["options"]["n_boot"] == 3 and doc["options"]["seed"] == 4
    assert "## Fitted numbers beside the paper's" in (d / "report.md").read_text()
    assert not (root / "rung-b").exists()


@pytest.mark.slow
def test_rejudge_decides_rejected_again_and_moves_nothing_else(tmp_path):
    # After a change of the rule that decides `rejected` alone (2026-12-02: a χ² far out counts),
    # `ladder_refit --rejudge` re-decides it from the goodness records fits.json keeps, without
    # refitting: θ's Eq. 7 fit of the 40 d rung had χ²/dof 5.2 at 14 dof (p = 5e-10), no trend,
    # and `rejected: false`.
    from analysis.ladder_refit import main, rejudge_fits
    root = tmp_path / "reproduction"
    d = make_rung(root, "rung-a", (0.887, 0.185), seed=1)
    (root / "ladder.yaml").write_text("rungs: [rung-a]\n")
    doc = json.loads((d / "fits.json").read_text())
    g = doc["fits"]["theta"]["meta"]["goodness"]
    g.update(dof=14, chi2=73.06, chi2_dof=5.219, chi2_p=5.35e-10, trend=False, trend_p=0.02, rejected=False)
    before = {k: v for k, v in doc.items()}
    (d / "fits.json").write_text(json.dumps(doc, indent=1))
    assert rejudge_fits(d) == ["theta"]
    after = json.loads((d / "fits.json").read_text())
    assert after["fits"]["theta"]["meta"]["goodness"]["rejected"] is True
    assert [x["fit"] for x in after["rejected"]] == ["theta"] and "far out" in after["rejected"][0]["what"]
    for k in before:                    # every fitted number as it was
        if k not in ("fits", "rejected"):
            assert after[k] == before[k], k
    assert after["fits"]["theta"]["params"] == before["fits"]["theta"]["params"]
    assert rejudge_fits(d) == []        # decided once, nothing moves the second time
    # The command: rejected again, and the report says so where the number was.
    assert main([str(root), "--rejudge"]) == 0
    report = (d / "report.md").read_text()
    assert "model rejected (χ²/dof = 5.22, χ² p = 5.4e-10)" in report


def test_ladder_script_refuses_a_rung_whose_results_hold_beds_or_pulls(tmp_path):
    """A resumed study would be timed from its resume: tools/ladder.sh measures only whole runs,
    and says how to record one by hand. A dry run's plan file alone is no reason to refuse
    (that case goes on to run the study, so it is not run here)."""
    results = tmp_path / "rung"
    (results / "pulls").mkdir(parents=True)
    config = tmp_path / "rung.yaml"
    config.write_text(f"results: {results}\n")
    r = subprocess.run([str(ROOT / "tools" / "ladder.sh"), str(config)], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 2 and "holds beds or pulls" in r.stderr and "ladder collect" in r.stderr, r.stderr


def test_the_sum_rule_figure_draws_the_deep_rungs_sums_beside_the_top_rungs(tmp_path):
    # (f)'s evidence: a top rung with no sum of its own still gets a figure when its `deep` rung has
    # read the sum rule at the paper's depths; without either there is nothing to draw.
    from types import SimpleNamespace

    from analysis.ladder.ladder_deep import deep_sums
    from analysis.ladder.ladder_summary import _sum_rule_figure
    spec = {"deep": [{"rung": "rung-deep", "show": {"sum_yield": "sum"}}]}
    assert deep_sums(tmp_path, spec) is None and deep_sums(tmp_path, {}) is None
    (tmp_path / "rung-deep").mkdir()
    deep_law_csv(tmp_path / "rung-deep" / "deep_law.csv")
    rows = deep_sums(tmp_path, spec)
    assert list(rows.quantity) == ["sum_yield"] and list(rows.rung) == ["rung-deep"]   # the shallow test is no sum
    assert rows.value.iloc[0] == pytest.approx(2.8016)
    empty = SimpleNamespace(sums=None, sums_drag=None, alpha=None, phi=None)
    assert _sum_rule_figure(empty, tmp_path, "rung-a") is None
    png = _sum_rule_figure(empty, tmp_path, "rung-a", rows)
    assert png is not None and png.stat().st_size > 1000
