"""The workflow's config schema states every granudrag key it exposes as the binary does.

`granudrag pour --schema`, `granudrag pull --schema` and `granudrag place --schema` print each key's type, range and
default from the one table the command line, validation and --help are built from. This test
compares them with workflow/schemas/config.schema.yaml for every config key that becomes a
command-line option (see pour_args / pull_args of the workflow's study module) and fails on any
difference of type, range or default.

Defaults: the schema must not give pour/pull keys a JSON Schema `default` (Snakemake's validate
fills defaults into every `pour:`/`pull:` block it sees, so a sweep's `pull:` block would reset
its system's settings to granudrag's defaults); it states them in the description instead, as
"(default: X)", and that X must be granudrag's.

The config reference's tables of the pour and pull keys (config/README.md) are generated from the
same --schema output by tools/schema_blocks.py; a stale copy fails here too.

The engine: $GRANUDRAG if set, else build/granudrag. A missing binary is a failure, not a skip.
"""
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag"))

RANGE_KEYWORDS = ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum")

# Config keys that become options, as the workflow passes them: (where in the schema, config key)
# -> (command, option). Under systems.<name>: lx, ly, grains and the pour/pull blocks; the sweep
# axes (each a number or a list of numbers) become pour options, a sweep's speeds pull options.
SYSTEM_KEYS = {"lx": "lx", "ly": "ly", "grains": "grains"}
AXES = {"D": "intruder_diameter", "depth": "depth", "z": "intruder_z", "mu": "mu", "kn": "kn",
        "gamman": "gamman", "seed": "seed", "seeds": "seed"}
SPEEDS = {"Fr": "froude", "V": "speed"}
# Not an option: the workflow turns it into gamman (gamman_ratio * kn^0.6).
NOT_OPTIONS = {"gamman_ratio"}
# Where the study deliberately asks for less than granudrag allows, and why. The test checks
# that the schema's range lies inside granudrag's and that the difference still exists.
NARROWER = {
    "D": "granudrag pours a bed without intruder for D = 0; a study's beds are pulled, so D > 0",
}


def cli_schema(command):
    if not BINARY.is_file():
        pytest.fail(f"no granudrag binary at {BINARY}: build it (cmake --build build) or set "
                    f"$GRANUDRAG to its path")
    out = subprocess.run([str(BINARY), command, "--schema"], capture_output=True, text=True,
                         check=True).stdout
    return json.loads(out)["properties"]


@pytest.fixture(scope="module")
def cli():
    return {command: cli_schema(command) for command in ("pour", "pull", "place")}


@pytest.fixture(scope="module")
def schema():
    with open(SCHEMA) as fh:
        return yaml.safe_load(fh)


def deref(schema, node):
    """The node a {"$ref": "#/$defs/x"} names, or the node itself."""
    ref = node.get("$ref")
    if ref is None:
        return node
    assert ref.startswith("#/"), ref
    target = schema
    for part in ref[2:].split("/"):
        target = target[part]
    return deref(schema, target)


def scalar_branches(schema, node):
    """The number schemas of a config key: itself, or both branches of 'a number or a list'."""
    node = deref(schema, node)
    if "oneOf" not in node:
        return [node]
    out = []
    for branch in node["oneOf"]:
        out.append(branch["items"] if branch.get("type") == "array" else branch)
    return out


def config_keys(schema):
    """(label, schema node, command, option, default_rule) of every exposed config key."""
    defs = schema["$defs"]
    system = schema["properties"]["systems"]["additionalProperties"]
    rows = []
    for key, option in SYSTEM_KEYS.items():
        # Required in a system: granudrag's default never applies.
        rows.append((f"systems.*.{key}", system["properties"][key], "pour", option, False))
    for command in ("pour", "pull", "place"):
        for key, node in defs[command]["properties"].items():
            rows.append((f"{command}.{key}", node, command, key, True))
    for key, node in defs["axes"]["properties"].items():
        if key in NOT_OPTIONS:
            continue
        assert key in AXES, f"axis '{key}' is mapped to no option: add it to AXES or NOT_OPTIONS"
        # A sweep or 'defaults' must give every axis (study.plan refuses a sweep without it).
        rows.append((f"axes.{key}", node, "pour", AXES[key], False))
    sweep = schema["properties"]["sweeps"]["items"]["properties"]
    for key, option in SPEEDS.items():
        rows.append((f"sweeps[].{key}", sweep[key], "pull", option, False))
    return rows


def json_type(node):
    t = node.get("type")
    types = set(t if isinstance(t, list) else [t])
    return types - {"null"}  # null is "not given": granudrag's default applies


def bounds(node):
    return {k: float(node[k]) for k in RANGE_KEYWORDS if k in node}


def lower(b):
    """(bound, exclusive) below."""
    if "exclusiveMinimum" in b:
        return b["exclusiveMinimum"], True
    return b.get("minimum", float("-inf")), False


def upper(b):
    """(bound, exclusive) above."""
    if "exclusiveMaximum" in b:
        return b["exclusiveMaximum"], True
    return b.get("maximum", float("inf")), False


def within(inner, outer):
    """Every number allowed by `inner` bounds is allowed by `outer` bounds."""
    (lo_in, lo_in_x), (lo_out, lo_out_x) = lower(inner), lower(outer)
    (hi_in, hi_in_x), (hi_out, hi_out_x) = upper(inner), upper(outer)
    lo_ok = lo_in > lo_out or (lo_in == lo_out and (lo_in_x or not lo_out_x))
    hi_ok = hi_in < hi_out or (hi_in == hi_out and (hi_in_x or not hi_out_x))
    return lo_ok and hi_ok


DEFAULT_RE = re.compile(r"\(default: ([^)]*)\)")


def differences(schema, cli):
    problems = []
    for label, node, command, option, default_rule in config_keys(schema):
        if option not in cli[command]:
            problems.append(f"{label}: granudrag {command} has no option --{option}")
            continue
        want = cli[command][option]
        for branch in scalar_branches(schema, node):
            if json_type(branch) != {want["type"]}:
                problems.append(f"{label}: type {sorted(json_type(branch))} in the schema, "
                                f"'{want['type']}' in granudrag {command} --{option}")
            have_b, want_b = bounds(branch), bounds(want)
            if label.split(".")[-1] in NARROWER:
                if have_b == want_b:
                    problems.append(f"{label}: listed in NARROWER but the ranges are now equal; "
                                    f"remove it from NARROWER")
                elif not within(have_b, want_b):
                    problems.append(f"{label}: range {have_b} in the schema is not inside "
                                    f"granudrag's {want_b}")
            elif have_b != want_b:
                problems.append(f"{label}: range {have_b} in the schema, {want_b} in granudrag "
                                f"{command} --{option}")
        if not default_rule:
            continue
        if "default" in node:
            problems.append(f"{label}: a JSON Schema 'default' would be filled into every "
                            f"{command} block; state it in the description as '(default: X)'")
        stated = DEFAULT_RE.search(node.get("description", ""))
        if "default" in want:
            if not stated:
                problems.append(f"{label}: the description does not state granudrag's default "
                                f"'(default: {want['default']})'")
            elif float(stated.group(1)) != float(want["default"]):
                problems.append(f"{label}: default {stated.group(1)} in the schema, "
                                f"{want['default']} in granudrag {command} --{option}")
        elif stated:
            problems.append(f"{label}: the schema states a default ({stated.group(1)}) but "
                            f"granudrag {command} --{option} has none")
    return problems


def test_schema_matches_granudrag(schema, cli):
    problems = differences(schema, cli)
    assert not problems, "config schema and granudrag differ:\n  " + "\n  ".join(problems)


def test_every_exposed_key_is_compared(schema):
    """Nothing in the pour/pull blocks, the systems or the axes escapes the comparison."""
    labels = {row[0] for row in config_keys(schema)}
    defs = schema["$defs"]
    for command in ("pour", "pull", "place"):
        for key in defs[command]["properties"]:
            assert f"{command}.{key}" in labels
    for key in defs["axes"]["properties"]:
        assert key in NOT_OPTIONS or f"axes.{key}" in labels
    assert {"systems.*.lx", "systems.*.ly", "systems.*.grains"} <= labels
    assert {"sweeps[].Fr", "sweeps[].V"} <= labels


def test_a_drifted_range_is_caught(schema, cli):
    """The comparison is not vacuous: change one range, type or default and it reports it."""
    drifted = json.loads(json.dumps(cli))
    drifted["pour"]["fill_fraction"]["maximum"] = 0.4
    drifted["pull"]["snapshots"]["type"] = "number"
    drifted["pull"]["shell"]["default"] = 3
    problems = "\n".join(differences(schema, drifted))
    assert "pour.fill_fraction: range" in problems
    assert "pull.snapshots: type" in problems
    assert "pull.shell: default" in problems


def test_schema_output_is_json_schema(cli):
    """--schema prints a JSON Schema the config validator (jsonschema) accepts as one."""
    import jsonschema
    for command in ("pour", "pull"):
        out = subprocess.run([str(BINARY), command, "--schema"], capture_output=True, text=True,
                             check=True).stdout
        doc = json.loads(out)
        jsonschema.Draft7Validator.check_schema(doc)
        assert doc["required"] == (["output"] if command == "pour" else ["bed", "output"])
        for key, prop in doc["properties"].items():
            assert prop["description"], key


def test_the_pour_and_pull_blocks_are_generated_from_the_engine_and_not_stale():
    """tools/schema_blocks.py writes the schema's pour/pull blocks from the engine's key tables;
    a key added to (or changed in) the engine without rerunning it fails here, with the diff."""
    if not BINARY.is_file():
        pytest.fail(f"no granudrag binary at {BINARY}: build it (cmake --build build) or set $GRANUDRAG")
    r = subprocess.run([sys.executable, str(ROOT / "tools" / "schema_blocks.py"), "--check", "--binary", str(BINARY)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def _schema_blocks():
    """tools/schema_blocks.py as a module."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("schema_blocks", ROOT / "tools" / "schema_blocks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_config_reference_tables_are_generated_from_the_engine_and_not_stale(cli):
    """config/README.md's tables of the pour and pull keys are schema_blocks.py's output: every config
    key of the schema's pour/pull blocks has a row with granudrag's default and range, and a table
    edited by hand (or an engine key changed without rerunning the tool) fails here."""
    tool = _schema_blocks()
    text = tool.REFERENCE.read_text()
    assert tool.render_reference(text, BINARY) == text, \
        "config/README.md's key tables are stale: run .venv/bin/python tools/schema_blocks.py"
    with open(SCHEMA) as fh:
        defs = yaml.safe_load(fh)["$defs"]
    for command in ("pour", "pull"):
        begin, end = tool.markers(command, "<!--")
        rows = text.split(begin, 1)[1].split(end, 1)[0].strip().splitlines()[2:]
        keys = [row.split("|")[1].strip().strip("`") for row in rows]
        assert keys == list(defs[command]["properties"]), command
        for row, key in zip(rows, keys):
            cells = [c.strip() for c in row.split("|")[1:-1]]
            want = cli[command][key]
            if "default" in want:
                assert float(cells[2]) == float(want["default"]), (command, key, cells[2])
            else:
                assert cells[2] == "–", (command, key)

    # The comparison is not vacuous: a hand-edited default is reported as stale.
    edited = text.replace("| `sample_interval` | sqrt(d/g) | 0.02 |", "| `sample_interval` | sqrt(d/g) | 0.03 |")
    assert edited != text
    assert tool.render_reference(edited, BINARY) == text


def test_the_reference_range_notation_is_the_engines():
    tool = _schema_blocks()
    assert tool._range({"minimum": 0, "maximum": 1}) == "[0, 1]"
    assert tool._range({"exclusiveMinimum": 0, "maximum": 0.35}) == "(0, 0.35]"
    assert tool._range({"exclusiveMinimum": 0.3, "exclusiveMaximum": 0.75}) == "(0.3, 0.75)"
    assert tool._range({"minimum": 0}) == ">= 0"
    assert tool._range({"exclusiveMaximum": 0.5}) == "< 0.5"
    assert tool._range({}) == "any"
    assert [tool._plain(v) for v in (1e-07, 2e8, 0.02, 20, -1, True, 9e18)] == \
        ["1e-7", "2e8", "0.02", "20", "-1", "true", "9e18"]


def test_the_bootstrap_count_is_declared_once(schema):
    """report.n_boot's schema default, the workflow's fallback and `analysis fit --n-boot` are N_BOOT."""
    from analysis.cli import parser
    from analysis.core.result import N_BOOT

    assert schema["properties"]["report"]["properties"]["n_boot"]["default"] == N_BOOT
    fit = parser().parse_args(["fit", "t.csv", "--output", "f.json"])
    assert fit.n_boot == N_BOOT


def test_the_contact_axes_follow_the_engines_ranges(monkeypatch, cli):
    """The sweep axes mu, kn and gamman are generated from `granudrag pour --schema`: a range the
    engine changes (here mu <= 2, a range no `$defs` entry states) reaches the schema's axis, and
    the schema's validator then refuses a value outside it."""
    import jsonschema
    tool = _schema_blocks()
    changed = {key: dict(node) for key, node in cli["pour"].items()}
    changed["mu"]["maximum"] = 2
    monkeypatch.setattr(tool, "engine_keys", lambda binary, command: changed)
    node = yaml.safe_load("\n".join(tool.axis_lines(BINARY, indent="")))
    assert node["kn"] == {"$ref": "#/$defs/positive_or_list"}
    check = jsonschema.Draft7Validator(node["mu"]).is_valid
    assert check(0.5) and check([0, 2]) and not check(2.5) and not check([0.5, -1])
