"""analysis.validation.validation_pool: one validation's comparisons pooled over several studies."""
import numpy as np
import pandas as pd
import pytest

from analysis.validation import validation_pool as pool
from analysis.validation.agreement import ValidationError


def comparison(study_dir, rows):
    """A comparison table as analysis.validation.validation writes it, in DIR/validate_active_region.csv."""
    study_dir.mkdir(parents=True)
    df = pd.DataFrame(rows)
    path = study_dir / "validate_active_region.csv"
    df.to_csv(path, index=False)
    return path


def row(D, R, rel, err, theta=0.0, theta_err=0.05, **extra):
    return dict(D=D, variant=R, reference=0, rel_diff=rel, rel_diff_err=err, theta_diff=theta,
                theta_diff_err=theta_err, **extra)


def test_pools_by_radius_over_D_with_inverse_variance_weights(tmp_path):
    a = comparison(tmp_path / "a", [row(2, 6, 0.02, 0.01), row(6, 18, 0.05, 0.02), row(2, 12, 0.0, 0.03)])
    b = comparison(tmp_path / "b", [row(4, 12, -0.01, 0.01)])
    out = pool.pool(pool.load([a, b]), "active_region").set_index("R_over_D")
    three = out.loc[3.0]
    d, w = np.array([0.02, 0.05, -0.01]), 1 / np.array([0.01, 0.02, 0.01]) ** 2
    m = (w * d).sum() / w.sum()
    assert three.rows == 3 and three.studies == 2   # 6 d at D = 2, 18 d at D = 6, 12 d at D = 4
    assert three.drag_diff == pytest.approx(m) and three.drag_err == pytest.approx(w.sum() ** -0.5)
    assert three.drag_z == pytest.approx(m / w.sum() ** -0.5)
    assert three.drag_chi2_dof == pytest.approx((w * (d - m) ** 2).sum() / 2)
    assert three.drag_above == 2
    six = out.loc[6.0]                          # 12 d is 6 D at D = 2, 3 D at D = 4
    assert six.rows == 1 and six.drag_diff == pytest.approx(0.0)
    # Where a table has no column, what studies ran at before it was recorded (sleep_speed 0.01,
    # the engine's default then, not its default now)
    assert out.loc[3.0, "wake_force"] == 0.5 and out.loc[3.0, "sleep_speed"] == 0.01
    assert out.loc[3.0, "sleep_time"] == 1.0


def test_rows_of_other_wake_tests_are_never_pooled_together(tmp_path):
    a = comparison(tmp_path / "a", [row(2, 6, 0.02, 0.01, wake_force=0.5), row(2, 6, 0.08, 0.01, wake_force=1.0)])
    b = comparison(tmp_path / "b", [row(2, 6, 0.04, 0.01)])     # before wake_force was recorded: 0.5
    out = pool.pool(pool.load([a, b]), "active_region").set_index("wake_force")
    assert out.loc[0.5].rows == 2 and out.loc[0.5].studies == 2
    assert out.loc[0.5].drag_diff == pytest.approx(0.03)
    assert out.loc[1.0].rows == 1 and out.loc[1.0].drag_diff == pytest.approx(0.08)


def test_wake_relative_pools_the_default_wake_test_across_stiffnesses(tmp_path):
    # 0.5 at K_n = 2e4 and 2 at 2e6 are both the default; 0.5 at 2e6 is a quarter of it
    a = comparison(tmp_path / "a", [row(2, 10, 0.02, 0.01, wake_force=0.5, kn=2e4)])
    b = comparison(tmp_path / "b", [row(2, 10, 0.04, 0.01, wake_force=2.0, kn=2e6),
                                    row(2, 10, 0.10, 0.01, wake_force=0.5, kn=2e6)])
    plain = pool.pool(pool.load([a, b]), "active_region")
    assert sorted(plain.rows) == [1, 2]                # by value: 0.5 (2e4 and 2e6) and 2
    out = pool.pool(pool.load([a, b]), "active_region", wake_relative=True).set_index(pool.WAKE_RELATIVE)
    assert out.loc[1.0].rows == 2 and out.loc[1.0].studies == 2
    assert out.loc[1.0].drag_diff == pytest.approx(0.03)
    assert out.loc[0.25].rows == 1 and out.loc[0.25].drag_diff == pytest.approx(0.10)
    text = pool.conclusion(out.reset_index(), "active_region")
    assert "5 D, wake_force_over_default 1, sleep_speed 0.01 (2 rows, 2 studies)" in text, text
    # without K_n the default cannot be known
    c = comparison(tmp_path / "c", [row(2, 10, 0.02, 0.01, wake_force=0.5)])
    with pytest.raises(ValidationError, match="lacks kn"):
        pool.pool(pool.load([c]), "active_region", wake_relative=True)


def test_rows_of_other_rest_tests_are_pooled_apart_and_named(tmp_path):
    a = comparison(tmp_path / "a", [row(2, 6, 0.02, 0.01, sleep_speed=0.01), row(2, 6, 0.0, 0.01, sleep_speed=0.001)])
    out = pool.pool(pool.load([a]), "active_region")
    assert sorted(out.sleep_speed) == [0.001, 0.01] and (out.rows == 1).all()
    text = pool.conclusion(out, "active_region")
    assert "3 D, sleep_speed 0.001 (1 rows" in text and "wake_force" not in text, text


def test_a_common_shift_below_every_rows_error_is_resolved_by_their_scatter(tmp_path):
    # Sixteen rows, each +1.5 % +- 0.2 % of scatter but with 4 % errors (the paired errors are
    # upper bounds): z stays below 2, the rows' own scatter says t >> 2.
    rng = np.random.default_rng(3)
    rows = [row(2, 6, 0.015 + 0.002 * rng.standard_normal(), 0.04, theta=0.01 * rng.standard_normal(),
                wake_force=0.5, sleep_speed=0.003) for _ in range(16)]
    out = pool.pool(pool.load([comparison(tmp_path / "a", rows)]), "active_region").iloc[0]
    assert out.agrees and abs(out.drag_z) < 2
    assert out.drag_t > 10 and out.drag_above == 16
    assert out.drag_scatter_err == pytest.approx(0.002 / 4, rel=0.4)
    assert abs(out.theta_t) < 4
    text = pool.conclusion(pool.pool(pool.load([tmp_path / "a" / "validate_active_region.csv"]), "active_region"),
                           "active_region")
    assert "3 D (16 rows, 1 study): drag +1.5" in text      # settings at the engine's defaults go unnamed
    assert "rows' own scatter resolves" in text and "drag at 3 D." in text
    assert "theta at" not in text


def test_no_shift_is_not_called_resolved(tmp_path):
    rng = np.random.default_rng(4)
    rows = [row(2, 6, 0.03 * rng.standard_normal(), 0.03) for _ in range(12)]
    out = pool.pool(pool.load([comparison(tmp_path / "a", rows)]), "active_region")
    text = pool.conclusion(out, "active_region")
    assert out.drag_chi2_dof.iloc[0] == pytest.approx(1.0, abs=0.7)
    assert "resolves" not in text


def test_write_and_bad_input(tmp_path):
    a = comparison(tmp_path / "a", [row(2, 6, 0.02, 0.01), row(6, 18, 0.05, 0.02), row(6, 18, 0.0, 0.02)])
    csv, md = pool.write([a], "active_region", tmp_path / "out")
    assert pd.read_csv(csv).rows.sum() == 3 and "Pooled over its studies" in md.read_text()
    assert not list((tmp_path / "out").glob("*.tmp"))
    with pytest.raises(ValidationError, match="no such comparison table"):
        pool.load([tmp_path / "missing.csv"])
    with pytest.raises(ValidationError, match="unknown validation study 'speed'"):
        pool.write([a], "speed", tmp_path / "out")
    bad = comparison(tmp_path / "bad", [dict(D=2, variant=6, drag=1.0)])
    with pytest.raises(ValidationError, match="lacks rel_diff, rel_diff_err"):
        pool.pool(pool.load([bad]), "active_region")


def test_the_pool_subcommand_prints_the_sentence_and_names_bad_input(tmp_path):
    from analysis.cli import main

    a = comparison(tmp_path / "a", [row(2, 6, 0.02, 0.01), row(6, 18, 0.05, 0.02)])
    assert main(["pool", "active_region", str(a), "--output-dir", str(tmp_path / "out")]) == 0
    assert (tmp_path / "out" / "pool_active_region.md").is_file()
    assert main(["pool", "active_region", str(tmp_path / "none.csv"), "--output-dir", str(tmp_path)]) == 2
