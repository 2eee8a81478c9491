"""Every engine default that the workflow or the analysis keeps a copy of is the engine's: each
copy against `granudrag <command> --schema`, which prints the key tables' own defaults (the
physics constants against `granudrag info`: test_physics.py). A default changed in C++ without
its copy fails here, naming both."""
import json
import os
import subprocess
from pathlib import Path

import pytest

from analysis.core import paper, physics
from analysis.validation.validation import SETTING_DEFAULTS
from granudrag_study import config as study_config
from granudrag_study import region_cost

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag"))

# (where the copy lives, its value, the command, the key)
COPIES = [
    ("granudrag_study.config.SETTLE_TIME_DEFAULT", study_config.SETTLE_TIME_DEFAULT, "pour", "max_settle_time"),
    ("granudrag_study.config.PLACE_SETTLE_TIME_DEFAULT", study_config.PLACE_SETTLE_TIME_DEFAULT, "place",
     "max_settle_time"),
    ("granudrag_study.config.SETTLE_DAMPING_DEFAULT", study_config.SETTLE_DAMPING_DEFAULT, "pour", "settle_damping"),
    ("granudrag_study.config.SETTLE_DAMPING_DEFAULT", study_config.SETTLE_DAMPING_DEFAULT, "place", "settle_damping"),
    ("granudrag_study.config.PLACE_MIN_SETTLE_TIME_DEFAULT", study_config.PLACE_MIN_SETTLE_TIME_DEFAULT, "place",
     "min_settle_time"),
    ("granudrag_study.region_cost.SLEEP_TIME_DEFAULT", region_cost.SLEEP_TIME_DEFAULT, "pull", "sleep_time"),
    ("granudrag_study.region_cost.WAKE_LOAD_DEFAULT", region_cost.WAKE_LOAD_DEFAULT, "pull", "wake_load"),
    *[(f"analysis.validation.validation.SETTING_DEFAULTS[{k!r}]", v, "pull", k) for k, v in SETTING_DEFAULTS.items()
      if k != "wake_force"],
]


@pytest.fixture(scope="module")
def schema():
    if not BINARY.is_file():
        pytest.fail(f"no granudrag binary at {BINARY}: build it (cmake --build build) or set $GRANUDRAG")

    def properties(command):
        out = subprocess.run([str(BINARY), command, "--schema"], capture_output=True, text=True, check=True)
        return json.loads(out.stdout)["properties"]
    return {command: properties(command) for command in ("pour", "pull", "place")}


@pytest.mark.parametrize("where, value, command, key", COPIES, ids=[c[0] for c in COPIES])
def test_a_copied_default_is_the_engines(schema, where, value, command, key):
    assert "default" in schema[command][key], f"granudrag {command} --{key} has no default, {where} copies one"
    assert value == schema[command][key]["default"], (
        f"{where} = {value}, granudrag {command} --{key} defaults to {schema[command][key]['default']}")


def test_the_wake_force_copied_is_the_engines_at_soft_beds():
    """wake_force has no row default (it follows K_n); the copy is the one of K_n <= 2e5."""
    assert SETTING_DEFAULTS["wake_force"] == physics.default_wake_force(2e4) == physics.default_wake_force(2e5)


def test_the_papers_contact_law_is_declared_once():
    assert paper.KN is physics.PAPER_KN


def test_the_analysis_contact_ranges_are_the_engines(schema):
    """analysis.core.physics.CONTACT_RANGES (the table's checks) against the contact keys' rows."""
    for key, (low, exclusive) in physics.CONTACT_RANGES.items():
        row = schema["pour"][key]
        bound = "exclusiveMinimum" if exclusive else "minimum"
        assert row.get(bound) == low and not {"maximum", "exclusiveMaximum"} & set(row), (
            f"analysis.core.physics.CONTACT_RANGES[{key!r}] = {(low, exclusive)}, granudrag pour --{key}: {row}")
    assert list(physics.in_contact_range("kn", [0.0, 2e4])) == [False, True]
    assert list(physics.in_contact_range("mu", [0.0, -0.1])) == [True, False]
