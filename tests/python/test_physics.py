"""analysis.core.physics against the engine: `granudrag info` prints the engine's own numbers
(time step, collision time, default damping, Froude number) as JSON with 17 significant
digits, so every formula the workflow and the analysis share with the engine is checked
here rather than trusted.

The engine: $GRANUDRAG if set, else build/granudrag (tools/test.sh builds it)."""

import json
import os
import subprocess
from pathlib import Path

import pytest

from analysis.core import physics

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag")).resolve()
REL = 1e-12


def info(*args):
    """The JSON object `granudrag info` prints for these options."""
    assert BINARY.is_file(), f"no granudrag binary at {BINARY}: build it (cmake --build build) or set GRANUDRAG"
    r = subprocess.run([str(BINARY), "info", *map(str, args)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, f"granudrag info {' '.join(map(str, args))} failed:\n{r.stderr}"
    return json.loads(r.stdout)


@pytest.mark.parametrize("kn", [2e4, 5e4, 2e6, 2e8])
def test_time_step_collision_time_and_damping_are_the_engines(kn):
    out = info("--kn", kn)
    assert out["kn"] == kn
    assert out["gamman"] == pytest.approx(physics.gamman_for(kn), rel=REL)
    assert out["collision_time"] == pytest.approx(physics.collision_time(kn), rel=REL)
    assert out["dt"] == pytest.approx(physics.default_dt(kn), rel=REL)
    assert out["max_dt"] == pytest.approx(physics.max_dt(kn), rel=REL)
    assert out["wake_force"] == pytest.approx(physics.default_wake_force(kn), rel=REL)


def test_paper_contact_law_is_the_engines_default():
    out = info()
    assert (out["kn"], out["gamman"]) == (physics.PAPER_KN, physics.PAPER_GAMMAN)
    assert physics.gamman_ratio(out["kn"], out["gamman"]) == pytest.approx(physics.PAPER_RATIO, rel=REL)
    assert out["dt"] == pytest.approx(physics.default_dt(physics.PAPER_KN), rel=REL)


def test_damping_from_youngs_modulus_keeps_the_restitution_curve():
    out = info("--youngs_modulus", 5e6, "--poisson_ratio", 0.3)
    assert out["gamman"] == pytest.approx(physics.gamman_for(out["kn"]), rel=REL)


def test_a_given_time_step_is_kept():
    out = info("--kn", 2e4, "--dt", 1e-4)
    assert out["dt"] == 1e-4
    assert out["max_dt"] == pytest.approx(physics.max_dt(2e4), rel=REL)


@pytest.mark.parametrize("D, V", [(2.0, 0.75), (1.5, 0.01), (4.0, 3.0), (6.0, 1.0)])
def test_froude_number_is_the_engines(D, V):
    out = info("--kn", 2e4, "--intruder_diameter", D, "--speed", V)
    assert (out["intruder_diameter"], out["speed"]) == (D, V)
    assert out["froude"] == pytest.approx(float(physics.froude(V, D)), rel=REL)


@pytest.mark.parametrize("D, Fr", [(2.0, 1.0), (1.5, 0.5), (4.0, 7.5)])
def test_speed_of_a_froude_number_is_the_engines(D, Fr):
    out = info("--kn", 2e4, "--intruder_diameter", D, "--froude", Fr)
    assert out["speed"] == pytest.approx(physics.froude_speed(Fr, D), rel=REL)
    assert out["froude"] == pytest.approx(Fr, rel=REL)
