import numpy as np
import pandas as pd
import pytest

from analysis.core.table import (
    COLUMNS,
    TableError,
    froude,
    load_csv,
    reference_params,
    save_csv,
    validate_table,
    yield_rows,
)


def test_froude_is_paper_eq4():
    # D = 2, V = 1: 2 * 1 * sqrt(4) / 3
    assert froude(1.0, 2.0) == pytest.approx(4.0 / 3.0)
    # For D >> d it tends to Eq. 5, 2 V sqrt(2 / (g D)).
    assert froude(1.0, 1e6) == pytest.approx(2.0 * np.sqrt(2.0 / 1e6), rel=1e-5)
    assert froude([1.0, 2.0], [2.0, 2.0]) == pytest.approx([4 / 3, 8 / 3])


def test_synthetic_table_is_valid(table):
    assert validate_table(table) is table
    assert list(COLUMNS) == [c for c in table.columns if c in COLUMNS]


def test_missing_column_is_named(table):
    with pytest.raises(ValueError, match=r"missing columns: kappa, run"):
        validate_table(table.drop(columns=["kappa", "run"]))


def test_ill_typed_column_is_named(table):
    bad = table.copy()
    bad["D"] = bad["D"].astype(str)
    bad["system"] = 1
    with pytest.raises(ValueError, match=r"D must be numeric.*system must be text"):
        validate_table(bad)


def test_missing_values_and_wrong_froude_are_rejected(table):
    bad = table.copy()
    bad.loc[3, "drag"] = np.nan
    with pytest.raises(ValueError, match=r"drag is missing or not finite in 1 row"):
        validate_table(bad)
    bad = table.copy()
    bad.loc[5, "Fr"] *= 1.1
    with pytest.raises(ValueError, match=r"Fr differs from froude"):
        validate_table(bad)
    ok = table.copy()
    ok.loc[0, "theta"] = np.nan          # observables may be missing
    validate_table(ok)


def test_csv_round_trip(table, tmp_path):
    path = tmp_path / "pulls.csv"
    save_csv(table, path)
    back = load_csv(path)
    extra = [c for c in table.columns if c not in COLUMNS]     # kept after the schema's columns
    pd.testing.assert_frame_equal(back, table[list(COLUMNS) + extra], check_dtype=False)


def test_loader_rejects_missing_file(tmp_path):
    with pytest.raises(TableError, match=r"nope\.csv: no such file"):
        load_csv(tmp_path / "nope.csv")


def test_loader_rejects_binary_and_hdf5(tmp_path):
    junk = tmp_path / "junk.csv"
    junk.write_bytes(bytes(range(256)) * 8)
    with pytest.raises(TableError, match=r"junk\.csv: is a binary file"):
        load_csv(junk)
    h5 = tmp_path / "run.h5"
    h5.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\x00" * 100)
    with pytest.raises(TableError, match=r"is an HDF5 file"):
        load_csv(h5)


def test_loader_rejects_foreign_and_corrupt_csv(table, tmp_path):
    foreign = tmp_path / "foreign.csv"
    foreign.write_text("name,score\nann,3\nbob,4\n")
    with pytest.raises(TableError, match=r"foreign\.csv: not a granudrag pull table: "
                                         r"missing columns: system, D,.*\(found: name, score\)"):
        load_csv(foreign)
    # A row cut short (e.g. an interrupted write) leaves required values empty.
    good = tmp_path / "good.csv"
    save_csv(table, good)
    lines = good.read_text().splitlines()
    cut = tmp_path / "cut.csv"
    cut.write_text("\n".join(lines[:-1] + [lines[-1][:20]]) + "\n")
    with pytest.raises(TableError, match=r"cut\.csv: not a granudrag pull table: "):
        load_csv(cut)
    # A row with more fields than the header is a parse error.
    extra = tmp_path / "extra.csv"
    extra.write_text("\n".join(lines[:3] + [lines[3] + ",1,2,3"]) + "\n")
    with pytest.raises(TableError, match=r"extra\.csv: not a readable CSV file"):
        load_csv(extra)


def test_helpers(table):
    assert set(yield_rows(table).V) == {0.01}
    assert reference_params(table) == (2e5, 500.0)


def test_write_csv_is_atomic(tmp_path):
    import pandas as pd

    from analysis.core.table import write_csv
    path = tmp_path / "out.csv"
    write_csv(pd.DataFrame({"a": [1.5, 2.0]}), path)
    assert pd.read_csv(path).a.tolist() == [1.5, 2.0]
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]          # no temporary left
    (tmp_path / "out.csv.tmp").mkdir()                                   # the next write fails ...
    with pytest.raises(OSError):
        write_csv(pd.DataFrame({"a": [9.0]}), path)
    assert pd.read_csv(path).a.tolist() == [1.5, 2.0]                    # ... and the old file stands


def point_runs(rng):
    """Run rows of two points: Fr 1 pulled in three beds, Fr 2 in one (it takes the pooled bed
    scatter), with the columns analysis.runs.runs reads beside the drag."""
    rows = []
    for fr, seeds in ((1.0, (1, 2, 3)), (2.0, (1,))):
        for s in seeds:
            drag = 100 * fr + 6 * rng.standard_normal()
            rows.append({"system": "I", "D": 2.0, "h": 6.4, "mu": 0.5, "kn": 2e4, "gamman": 199.0,
                         "V": fr / float(froude(1.0, 2.0)), "Fr": fr, "drag": drag, "drag_err": 2.0 + s,
                         "n_contacts": 9.0, "theta": 1.5, "Z": 3.5, "kappa": 1.0, "drag_dof": 8.0,
                         "run": f"pulls/system~I/D~2/h~6.5/mu~0.5/seed~{s}/Fr~{fr:g}", "seed": float(s),
                         "plateau": s != 2, "plateau_engine": False, "drag_err_engine": 3.0 * (2.0 + s),
                         "drag_cumulative": 0.9 * drag + rng.standard_normal(), "drag_cumulative_err": 1.0 + s})
    df = pd.DataFrame(rows)
    df["Fr"] = froude(df.V, df.D)
    return df


def test_the_point_table_aggregates_the_cumulative_drag_as_the_drag_and_gives_the_beds_spread():
    from analysis.core.table import between_bed_scatter, combine_beds
    df = point_runs(np.random.default_rng(4))
    pts = combine_beds(df)
    three, one = pts.iloc[0], pts.iloc[1]
    g = df.iloc[:3]
    y, e, yc, ec = g.drag.to_numpy(), g.drag_err.to_numpy(), g.drag_cumulative.to_numpy(), g.drag_cumulative_err
    # drag_err's rule, sqrt(max(s^2, W)/k), on the cumulative drag and on the engine's errors
    assert three.drag_cumulative == pytest.approx(yc.mean())
    assert three.drag_cumulative_err == pytest.approx(np.sqrt(max(np.var(yc, ddof=1), np.mean(ec ** 2)) / 3))
    assert three.drag_err_engine == pytest.approx(
        np.sqrt(max(np.var(y, ddof=1), np.mean(g.drag_err_engine.to_numpy() ** 2)) / 3))
    assert three.drag_bed_sd == pytest.approx(np.std(y, ddof=1))
    assert three.drag_bed_sd_ratio == pytest.approx(np.std(y, ddof=1) / e.mean())
    assert three.drag_bed_sd_ratio_engine == pytest.approx(np.std(y, ddof=1) / g.drag_err_engine.mean())
    assert not three.plateau and not three.plateau_engine          # a bed without: the point without
    # One bed: no spread; the pooled relative bed scatter on top of its errors, as its drag's
    r2 = between_bed_scatter(df)[0]
    assert np.isnan(one.drag_bed_sd) and np.isnan(one.drag_bed_sd_ratio)
    assert one.drag_err == pytest.approx(np.sqrt(3.0 ** 2 + r2 * one.drag ** 2))
    assert one.drag_cumulative_err == pytest.approx(np.sqrt(2.0 ** 2 + r2 * one.drag_cumulative ** 2))
    assert one.plateau and not one.plateau_engine
    # A run table from before these columns (a ladder rung's recorded runs.csv) still combines.
    old = combine_beds(df.drop(columns=["drag_cumulative", "drag_cumulative_err", "drag_err_engine",
                                        "plateau_engine"]))
    assert "drag_cumulative" not in old and "drag_bed_sd_ratio_engine" not in old
    assert old.drag_bed_sd_ratio.iloc[0] == pytest.approx(three.drag_bed_sd_ratio)
