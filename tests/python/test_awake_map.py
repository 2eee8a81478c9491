"""bench/awake_map.py: which grains outside the active region are awake, and whether they drift."""

import importlib.util
from pathlib import Path

import numpy as np

_SPEC = importlib.util.spec_from_file_location("awake_map", Path(__file__).parents[2] / "bench" / "awake_map.py")
awake_map = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(awake_map)


def _frames():
    # A 20 d x 20 d box, the intruder at (1, 10, 5): grain 1 sits 2 d from it across the periodic
    # x boundary (inside R = 4), grains 2-4 far from it, grain 5 frozen. Over the 2 time units
    # since the frame before, grain 3 drifted 4e-3 d (2e-3 per unit: 20x the rest test of 1e-4),
    # grain 4 1e-4 d (slower than the rest test) and grain 2, asleep, 0.5 d across the x boundary
    # (from 19.9 to 0.4: periodic, not 19.5 d).
    x = np.array([[1.0, 10, 5], [19.0, 10, 5], [0.4, 0, 2], [11.0, 10, 8], [11.0, 2, 8], [11.0, 2, 0.5]])
    before = x.copy()
    before[2, 0], before[3, 2], before[4, 0] = 19.9, 7.996, 10.9999
    v = np.zeros_like(x)
    v[1] = (0.5, 0, 0)  # inside R, moving: not counted
    v[3] = (0, 0, 1e-3)  # outside, awake
    v[4] = (5e-5, 0, 0)  # outside, awake
    species = np.array([2, 0, 0, 0, 0, 1])
    return x, v, before, species


def test_the_grains_outside_the_radius_are_counted_awake_by_velocity_and_drifting_by_displacement():
    x, v, before, species = _frames()
    s = awake_map.frame_summary(x, v, before, 2.0, species, radius=4.0, lx=20.0, ly=20.0, rest_speed=1e-4)
    assert s["outside"] == 3  # grains 2-4: grain 1 is 2 d away through the boundary, not 18 d
    assert s["awake"] == 2 and s["asleep"] == 1 / 4  # grain 2 of the four mobile grains sleeps
    # drifting: grain 2 (0.25 per unit, though asleep now) and grain 3 (2e-3); x10: both
    assert s["drifting"] == 2 and s["drifting10"] == 2 and s["awake_drifting"] == 1
    assert s["above"] == 1.0  # both awake grains are above the intruder's centre (z 8 > 5)
    # Depth from the top grain (z 8): the awake grains at depth 0, the sleeping one at 6.
    assert np.allclose(s["awake_by_depth"], [1.0, 0.0]) and np.allclose(s["drifting_by_depth"], [0.5, 1.0])
    # Horizontally 10.0, 10 and 12.8 d from the intruder: one 5 d band, two of its three grains awake.
    assert np.allclose(s["awake_by_horizontal"], [np.nan, np.nan, 2 / 3], equal_nan=True)
