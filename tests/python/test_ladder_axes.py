"""analysis.ladder.ladder_axes: the drag of the same points in rungs of wider boxes, stiffer contacts or longer pulls,
each against the previous rung's along the axis, the summary, and their place in `ladder table`'s
files."""
import math

import numpy as np
import pandas as pd
import pytest
from test_ladder import FR, make_rung, point_table

from analysis.core.point_errors import pooled_drag_err
from analysis.core.table import save_csv
from analysis.ladder.ladder import (
    BOX,
    LENGTH,
    STIFFNESS,
    LadderError,
    axis_summary,
    box_axis,
    length_axis,
    stiffness_axis,
    write_ladder,
)

SCALED = ("drag", "drag_err", "drag_err_within", "drag_err_between")


def boxed(lx, factor=1.0, h_shift=0.0, kn=None, distance=12.0):
    """point_table's rung (the same noise for every box: seed 0) in a box lx wide, pulls of
    `distance` (a pull ends a little past its target), its drags and their errors times
    factor(Fr), its depths shifted by h_shift."""
    t = point_table().assign(lx=float(lx), ly=float(lx), distance=distance + 0.003)
    f = np.array([factor(fr) if callable(factor) else factor for fr in t.Fr])
    for col in SCALED:
        t[col] = t[col] * f
    t["drag_var_excess"] = t.drag_var_excess * f ** 2
    t["h"] = t.h + h_shift
    if kn is not None:
        t["kn"] = kn
    return t


def write_rungs(root, rungs):
    """A ladder of rungs (name, label, point table) in order, each with its claims' files
    (make_rung) and the given table; then `ladder table` (write_ladder). Returns the paths written."""
    (root / "ladder.yaml").write_text(
        "rungs:\n" + "".join(f"  - {{name: {name}, label: '{label}'}}\n" for name, label, _ in rungs))
    for name, _, table in rungs:
        save_csv(table, make_rung(root, name, (0.887, 0.185), seed=1) / "table.csv")
    return write_ladder(root, n_boot=5, seed=0)


def test_each_box_is_compared_with_the_next_narrower_one():
    step = lambda fr: 1.2 if fr <= 4 else 1.8     # noqa: E731
    box = box_axis({"b12": boxed(12), "b20": boxed(20, step), "b30": boxed(30, lambda fr: 1.2 * step(fr))})
    assert set(box.lx) == {12.0, 20.0, 30.0} and set(box.D) == {2.0, 3.0}
    assert len(box) == 3 * 2 * len(FR)
    narrowest = box[box.lx == 12]
    assert narrowest.ratio.isna().all() and narrowest.previous.isna().all()
    b20, b30 = box[box.lx == 20], box[box.lx == 30]
    assert (b20.previous == 12).all() and (b30.previous == 20).all()    # not the narrowest
    assert b20.ratio.to_numpy() == pytest.approx([step(fr) for fr in b20.Fr])
    assert b30.ratio.to_numpy() == pytest.approx(np.full(len(b30), 1.2))
    # Relative errors in quadrature; z the difference over its error.
    t = point_table()
    first = (t.D == 2) & np.isclose(t.Fr, FR[0])
    rel = (pooled_drag_err(t)[first] / t.drag[first]).iloc[0]
    one = b20[(b20.D == 2) & np.isclose(b20.Fr, FR[0])].iloc[0]
    narrow = narrowest[(narrowest.D == 2) & np.isclose(narrowest.Fr, FR[0])].iloc[0]
    assert one.ratio_err == pytest.approx(1.2 * math.sqrt(2) * rel)
    assert one.z == pytest.approx((one.drag - narrow.drag) / math.hypot(one.drag_err, narrow.drag_err))
    assert one.drag_err == pytest.approx(1.2 * narrow.drag_err)


def test_points_of_another_stiffness_or_depth_are_not_compared():
    assert box_axis({"b12": boxed(12), "deeper": boxed(20, h_shift=3.0)}).empty
    assert box_axis({"b12": boxed(12), "stiffer": boxed(20, kn=2e6)}).empty
    assert box_axis({"b12": boxed(12)}).empty and box_axis({}).empty
    near = box_axis({"b12": boxed(12), "b20": boxed(20, 1.1, h_shift=0.5)})
    assert len(near) == 2 * 2 * len(FR) and near.ratio.dropna().to_numpy() == pytest.approx(1.1)


@pytest.mark.slow
def test_a_rung_and_its_in_place_extension_are_one_point_on_the_axis(tmp_path):
    # crossover-k2e6-box40-full grew in place from crossover-k2e6-box40 (a copy of its results
    # directory, with a bed and speeds added): its points hold the other's pulls. Against the
    # 30 d box the 40 d box is one rung, the extension, not both side by side.
    tables = {"b30": boxed(30), "b40": boxed(40, 1.1), "b40-full": boxed(40, 1.05)}
    both = box_axis(tables)
    assert set(both[both.lx == 40].rung) == {"b40", "b40-full"}             # counted twice before
    box = box_axis(tables, extends={"b40-full": "b40"})
    assert set(box[box.lx == 40].rung) == {"b40-full"} and len(box[box.lx == 40]) == 2 * len(FR)
    assert box[box.lx == 40].ratio.to_numpy() == pytest.approx(1.05)
    s = axis_summary(box, BOX)
    assert s.n_points.sum() == 2 * len(FR)                                  # 2 D, each point once
    # An extension whose base is not among the tables (or no extension at all) drops nothing.
    assert set(box_axis({"b30": boxed(30), "b40-full": boxed(40)}, extends={"b40-full": "b40"}).rung) == \
        {"b30", "b40-full"}
    # ladder.yaml says which rung extends which, and `ladder table` counts each point once.
    (tmp_path / "ladder.yaml").write_text(
        "rungs:\n  - {name: b30, label: '30 d'}\n  - {name: b40, label: '40 d'}\n"
        "  - {name: b40-full, label: '40 d, more', extends: b40}\n")
    for name, t in tables.items():
        save_csv(t, make_rung(tmp_path, name, (0.887, 0.185), seed=1) / "table.csv")
    write_ladder(tmp_path, n_boot=5, seed=0)
    written = pd.read_csv(tmp_path / "box_axis.csv")
    assert set(written.rung) == {"b30", "b40-full"}
    assert "extends `b40` in place" in (tmp_path / "ladder.md").read_text()
    (tmp_path / "ladder.yaml").write_text("rungs:\n  - {name: b30}\n  - {name: b40-full, extends: b39}\n")
    with pytest.raises(LadderError, match="b40-full extends b39, which is not another listed rung"):
        write_ladder(tmp_path, n_boot=5, seed=0)


def test_summary_splits_at_fr_4_and_counts_the_points_beyond_two_errors():
    step = lambda fr: 1.0 if fr <= 4 else 2.0     # noqa: E731
    s = axis_summary(box_axis({"b12": boxed(12), "b20": boxed(20, step)}), BOX)
    assert len(s) == 4 and set(s.D) == {2.0, 3.0}
    low, high = s[s.fr_lo == 0].iloc[0], s[s.fr_lo == 4].iloc[0]
    assert low.n_points == (FR <= 4).sum() and high.n_points == (FR > 4).sum()
    assert low.ratio_median == pytest.approx(1.0) and low.n_beyond_2sigma == 0
    assert high.ratio_min == pytest.approx(2.0) and high.n_beyond_2sigma == high.n_points


@pytest.mark.slow
def test_ladder_table_writes_the_box_axis(tmp_path):
    written = write_rungs(tmp_path, [("narrow", "12 d box", boxed(12)), ("wide", "20 d box", boxed(20, 1.5))])
    box = pd.read_csv(tmp_path / "box_axis.csv")
    assert box[box.lx == 20].ratio.to_numpy() == pytest.approx(1.5)
    assert tmp_path / "box_axis.png" in written and (tmp_path / "box_axis.png").stat().st_size > 1000
    md = (tmp_path / "ladder.md").read_text()
    assert "### The drag against the box's width" in md and "![drag against the box's width](box_axis.png)" in md
    assert "| K_n 2e+05, pull 12 d | 2 | 12 d → 20 d | ×1.50 (1.50 – 1.50;" in md
    assert pd.read_csv(tmp_path / "stiffness_axis.csv").empty and "contacts' stiffness" not in md


@pytest.mark.slow
def test_ladder_without_two_boxes_writes_no_figure(tmp_path):
    for name in ("box", "stiffness", "length"):
        (tmp_path / f"{name}_axis.png").write_bytes(b"stale")
    write_rungs(tmp_path, [("only", "one box", boxed(12))])
    assert not any((tmp_path / f"{name}_axis.png").exists() for name in ("box", "stiffness", "length"))
    assert pd.read_csv(tmp_path / "box_axis.csv").empty
    assert "box's width" not in (tmp_path / "ladder.md").read_text()


def test_each_stiffness_is_compared_with_the_next_softer_one_in_the_same_box():
    # The paper's shape (Sec. III I): the level moves with K_n, the crossover does not, so a ratio
    # that changes across Fr 4 is what the axis is there to show.
    bend = lambda fr: 1.3 if fr <= 4 else 0.8     # noqa: E731
    tables = {"k5": boxed(12, kn=2e5), "k6": boxed(12, 1.3, kn=2e6), "k7": boxed(12, lambda fr: 1.3 * bend(fr), kn=2e7),
              "k6-wide": boxed(20, 2.0, kn=2e6)}
    axis = stiffness_axis(tables)
    assert set(axis.lx) == {12.0} and set(axis.kn) == {2e5, 2e6, 2e7}    # the 20 d rung has no partner
    k6, k7 = axis[axis.kn == 2e6], axis[axis.kn == 2e7]
    assert (k6.previous == 2e5).all() and (k7.previous == 2e6).all()     # the next softer, not the softest
    assert k6.ratio.to_numpy() == pytest.approx(1.3)
    assert k7.ratio.to_numpy() == pytest.approx([bend(fr) for fr in k7.Fr])
    s = axis_summary(axis, STIFFNESS)
    step = s[(s.kn == 2e7) & (s.D == 2)]
    assert step[step.fr_lo == 0].ratio_median.iloc[0] == pytest.approx(1.3)
    assert step[step.fr_lo == 4].ratio_median.iloc[0] == pytest.approx(0.8)
    # The box axis of the same tables pairs only the two boxes at 2e6.
    box = box_axis(tables)
    assert set(box.kn) == {2e6} and box.ratio.dropna().to_numpy() == pytest.approx(2.0 / 1.3)


@pytest.mark.slow
def test_ladder_table_writes_the_stiffness_axis(tmp_path):
    written = write_rungs(tmp_path, [("soft", "K_n 2e6", boxed(20, kn=2e6)),
                                     ("stiff", "K_n 2e7", boxed(20, 0.7, kn=2e7))])
    assert tmp_path / "stiffness_axis.png" in written
    assert pd.read_csv(tmp_path / "stiffness_axis.csv").ratio.dropna().to_numpy() == pytest.approx(0.7)
    md = (tmp_path / "ladder.md").read_text()
    assert "### The drag against the contacts' stiffness" in md and "(stiffness_axis.png)" in md
    assert "| box 20 d, pull 12 d | 3 | 2e+06 → 2e+07 | ×0.70 (0.70 – 0.70;" in md
    assert "box's width" not in md


def test_each_pull_is_compared_with_the_next_shorter_one_and_the_other_axes_hold_the_length():
    # A rung of longer pulls in the same box and K_n is a step along the pull's length only: the
    # box axis must pair the 30 d box with the 20 d rung of its own pull length, not the longer one.
    drift = lambda fr: 1.0 if fr <= 4 else 1.25     # noqa: E731
    tables = {"b20": boxed(20, kn=2e6), "b20-long": boxed(20, drift, kn=2e6, distance=20.0),
              "b30": boxed(30, 1.1, kn=2e6), "k7": boxed(20, 0.9, kn=2e7)}
    length = length_axis(tables)
    assert set(length.distance) == {12.0, 20.0} and set(length.lx) == {20.0} and set(length.kn) == {2e6}
    long = length[length.distance == 20]
    assert (long.previous == 12).all()
    assert long.ratio.to_numpy() == pytest.approx([drift(fr) for fr in long.Fr])
    s = axis_summary(length, LENGTH)
    assert set(s.distance) == {20.0} and s[s.fr_lo == 4].ratio_median.to_numpy() == pytest.approx(1.25)
    box = box_axis(tables)
    assert set(box.distance) == {12.0} and box.ratio.dropna().to_numpy() == pytest.approx(1.1)
    stiff = stiffness_axis(tables)
    assert set(stiff.distance) == {12.0} and stiff.ratio.dropna().to_numpy() == pytest.approx(0.9)


@pytest.mark.slow
def test_ladder_table_writes_the_length_axis(tmp_path):
    written = write_rungs(tmp_path, [("short", "12 d pulls", boxed(20, kn=2e6, distance=12.0)),
                                     ("long", "20 d pulls", boxed(20, 1.1, kn=2e6, distance=20.0))])
    assert tmp_path / "length_axis.png" in written
    assert pd.read_csv(tmp_path / "length_axis.csv").ratio.dropna().to_numpy() == pytest.approx(1.1)
    md = (tmp_path / "ladder.md").read_text()
    assert "### The drag against the pull's length" in md and "(length_axis.png)" in md
    assert "| K_n 2e+06, box 20 d | 3 | 12 d → 20 d | ×1.10 (1.10 – 1.10;" in md
    assert "box's width" not in md and "contacts' stiffness" not in md
