import numpy as np
import pandas as pd
import pytest

from analysis.table import COLUMNS, TableError, froude, load_csv, reference_params, save_csv, validate_table, yield_rows


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

    from analysis.table import write_csv
    path = tmp_path / "out.csv"
    write_csv(pd.DataFrame({"a": [1.5, 2.0]}), path)
    assert pd.read_csv(path).a.tolist() == [1.5, 2.0]
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]          # no temporary left
    (tmp_path / "out.csv.tmp").mkdir()                                   # the next write fails ...
    with pytest.raises(OSError):
        write_csv(pd.DataFrame({"a": [9.0]}), path)
    assert pd.read_csv(path).a.tolist() == [1.5, 2.0]                    # ... and the old file stands
