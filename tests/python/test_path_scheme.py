"""analysis.core.path_scheme: the study's paths declared once (issue 75) -- the pattern, the regex, the
key and the reader's parser all come from it, and no module holds a copy of its components."""
import math
import re
from pathlib import Path

import pandas as pd
import pytest

from analysis.core import path_scheme as scheme
from analysis.runs.runs import path_parameters

ROOT = Path(__file__).resolve().parents[2]

BED_FIELDS = {"system": "I", "D": "3", "place": "z", "pos": "13.5", "mu": "0.5", "kn": "2e6",
              "gn": "3154.7867", "seed": "1"}
BED_KEY = "system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~3154.7867/seed~1"


def test_the_declaration_names_each_table_column_once():
    assert scheme.COLUMN_OF == {"system": "system", "D": "D", "h": "h_requested", "z": "z_requested",
                                "mu": "mu", "kn": "kn", "gn": "gamman", "seed": "seed", "Fr": "Fr", "V": "V"}
    assert [c.names for c in scheme.COLUMN] == [("system",), ("mu",), ("kn",), ("gn",), ("seed",)]
    with pytest.raises(ValueError, match="one column per name"):
        scheme.Component("x", ("a", "b"), ("a",), choice="c")


@pytest.mark.parametrize("components, fields, text", [
    (scheme.BED, BED_FIELDS, BED_KEY),
    (scheme.BED, dict(BED_FIELDS, place="h", pos="7", system="II_damped", kn="2e4", gn="199.05359", seed="3"),
     "system~II_damped/D~3/h~7/mu~0.5/kn~2e4/gn~199.05359/seed~3"),
    (scheme.COLUMN, {k: BED_FIELDS[k] for k in ("system", "mu", "kn", "gn", "seed")},
     "system~I/mu~0.5/kn~2e6/gn~3154.7867/seed~1"),
    (scheme.PULL, dict(BED_FIELDS, kind="Fr", value="4"), BED_KEY + "/Fr~4"),
    ((scheme.SPEED,), {"kind": "V", "value": "0.1"}, "V~0.1"),
])
def test_key_pattern_regex_and_parser_agree_for_every_kind_of_path(components, fields, text):
    assert scheme.key(components, fields) == text
    assert scheme.parse(components, text) == fields
    assert re.fullmatch(scheme.pattern(components), text)
    assert re.compile(scheme.pattern(components)).groups == 0   # a Snakemake wildcard constraint
    # The reader's parser, from the same declaration: the path's names to the table's columns.
    named = path_parameters(f"results/x/{text}/run.h5")
    assert named == {c.names[0] if not c.choice else fields[c.choice]: fields[c.field] for c in components}


@pytest.mark.parametrize("text", [
    "system~I/D~3/x~13.5/mu~0.5/kn~2e6/gn~3154.7867/seed~1",      # no such placement
    "system~I/D~3/mu~0.5/kn~2e6/gn~3154.7867/seed~1",              # a component missing
    "system~I/D~3/z~13.5/kn~2e6/mu~0.5/gn~3154.7867/seed~1",      # out of order
    "system~I/D~3/z~13.5/mu~0.5/kn~2e6/gn~3154.7867/seed~1/",     # a trailing slash
    "system~I/D~3~4/z~13.5/mu~0.5/kn~2e6/gn~3154.7867/seed~1",    # a separator in a value
])
def test_what_is_not_a_bed_matches_neither_the_pattern_nor_the_regex(text):
    assert scheme.parse(scheme.BED, text) is None
    assert not re.fullmatch(scheme.pattern(scheme.BED), text)


def test_a_pattern_restricted_to_some_values():
    only = scheme.pattern(scheme.BED, system=["I", "a.b"])
    assert re.fullmatch(only, BED_KEY) and not re.fullmatch(only, BED_KEY.replace("system~I", "system~aXb"))
    assert not re.fullmatch(scheme.pattern(scheme.BED, system=[]), BED_KEY)


def test_a_name_outside_the_declaration_is_refused_and_ignored_by_the_reader():
    with pytest.raises(ValueError, match="not one of"):
        scheme.key(scheme.BED, dict(BED_FIELDS, place="y"))
    with pytest.raises(ValueError, match="not a path component"):
        scheme.part("gamman", "1")
    assert path_parameters("/home/u/box~3/system~I/D~2/run.h5") == {"system": "I", "D": "2"}
    assert scheme.name_of("seed~2") == "seed" and scheme.name_of("seeds~2") is None


def _committed_runs():
    return sorted(p.relative_to(ROOT) for p in (ROOT / "results" / "reproduction").glob("**/runs.csv"))


@pytest.mark.parametrize("table", _committed_runs(), ids=str)
def test_the_committed_tables_paths_read_back_to_their_rows(table):
    """Every run of a committed runs.csv: its path's components, read by the declaration, give the
    row's path columns and agree with the columns the file gave; its bed formats back to itself.
    (A table older than a column, z_requested, lacks it.)"""
    runs = pd.read_csv(ROOT / table)
    assert len(runs)
    for row in runs.itertuples():
        named = path_parameters(row.path)
        for name, text in named.items():
            column = scheme.COLUMN_OF[name]
            have = getattr(row, column, None)
            if have is None:
                continue
            if column == "system":
                assert str(have) == text
            else:
                assert math.isclose(float(text), have, rel_tol=1e-5), (row.path, name)
        for column in ("h_requested", "z_requested", "seed"):
            if column in runs and not any(scheme.COLUMN_OF[n] == column for n in named):
                assert math.isnan(getattr(row, column)), (row.path, column)
        bed, speed = row.run.split("/", 1)[1].rsplit("/", 1)
        fields = scheme.parse(scheme.BED, bed)
        assert scheme.key(scheme.BED, fields) == bed and scheme.parse((scheme.SPEED,), speed)


# Where the code lives (tests build their paths literally, on purpose).
SOURCES = ["analysis", "workflow", "tools", "bench"]
# The makings of a second copy of the scheme: a component name followed by its separator and
# then a regex, a format field or a quote; a group or a value's class after a separator (an example
# path in a docstring, `mu~0.5`, is none of these).
COPY = re.compile(r"\b(" + "|".join(map(re.escape, scheme.COLUMN_OF)) + r")~(\[|\(|\{|\"|')"
                  + "|" + re.escape(scheme.SEP + "(?P<") + "|" + re.escape(scheme.VALUE))


def test_no_module_but_the_declaration_spells_out_a_path_component():
    mine = ROOT / "analysis" / "core" / "path_scheme.py"
    found = []
    for top in SOURCES:
        for p in sorted((ROOT / top).rglob("*")):
            if p.suffix not in (".py", ".smk", ".sh") and p.name != "Snakefile" or p == mine:
                continue
            for n, line in enumerate(p.read_text(errors="replace").splitlines(), 1):
                if COPY.search(line):
                    found.append(f"{p.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not found, "a copy of the path scheme outside analysis/core/path_scheme.py:\n" + "\n".join(found)
    # ... and the check sees one: the forms the copies had.
    for line in ('r"system~[^/~]+/D~"', 'f"/kn~{self.kn}/gn~{self.gn}"', 'p.startswith("seed~")',
                 '(?P<place>[hz])~(?P<pos>', 'f"Fr~{fmt(v)}"'):
        assert COPY.search(line), line
