"""bench/awake_map.py: which grains outside the active region are awake, and whether they move."""

import importlib.util
from pathlib import Path

import numpy as np

_SPEC = importlib.util.spec_from_file_location("awake_map", Path(__file__).parents[2] / "bench" / "awake_map.py")
awake_map = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(awake_map)


def _frame():
    # A 20 d x 20 d box, the intruder at (1, 10, 5): grain 1 sits 2 d from it across the periodic
    # x boundary (inside R = 4), grains 2-4 far from it, grain 5 frozen.
    x = np.array([[1.0, 10, 5], [19.0, 10, 5], [11.0, 10, 2], [11.0, 10, 8], [11.0, 2, 8], [11.0, 2, 0.5]])
    v = np.zeros_like(x)
    v[1] = (0.5, 0, 0)  # inside R, moving: not counted
    v[3] = (0, 0, 1e-3)  # outside, awake, 10x faster than the rest test of 1e-4
    v[4] = (5e-5, 0, 0)  # outside, awake, slower than the rest test
    species = np.array([2, 0, 0, 0, 0, 1])
    return x, v, species


def test_an_awake_grain_is_one_that_moves_and_only_those_outside_the_radius_count():
    x, v, species = _frame()
    s = awake_map.frame_summary(x, v, species, radius=4.0, lx=20.0, ly=20.0, rest_speed=1e-4)
    assert s["outside"] == 3  # grains 2-4: grain 1 is 2 d away through the boundary, not 18 d
    assert s["awake"] == 2 and s["moving"] == 1 and s["moving10"] == 0  # 1e-3 is not faster than 10 x 1e-4
    assert s["asleep"] == 1 / 4  # grain 2 of the four mobile grains
    assert s["above"] == 1.0  # both awake grains are above the intruder's centre (z 8 > 5)
    # Depth from the top grain (z 8): the awake grains at depth 0, the sleeping one at 6.
    assert np.allclose(s["awake_by_depth"], [1.0, 0.0])
    # Horizontally 10, 10 and 12.8 d from the intruder: all in the third 5 d band, two of three awake.
    assert np.allclose(s["awake_by_horizontal"], [np.nan, np.nan, 2 / 3], equal_nan=True)
