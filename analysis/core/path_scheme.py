"""The study's path scheme, declared once: the `name~value` directories that name a bed, a
column and a pull, their order, and the table column each one fills.

    <results>/beds/system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.054/seed~1/bed.h5
    <results>/columns/system~I/mu~0.5/kn~2e4/gn~199.054/seed~1/column.h5
    <results>/pulls/system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.054/seed~1/Fr~1/run.h5

Everything that writes or reads such a path is derived from BED, COLUMN and SPEED below: the
workflow's wildcard patterns, its regexes and keys (granudrag_study.paths: Bed, Pull) and the run
reader's parser (analysis.runs.runs). The names in paths are short and fixed, since studies on disk
carry them (`gn`, not the table's `gamman`); a component's `columns` say which table column each
name is. A component whose name is itself a choice (a bed placed by depth `h~` or by height `z~`;
a speed as a Froude number `Fr~` or as `V~`) keeps that choice in a field of its own.

This module imports nothing of the project: the analysis and the workflow's library both use it.
"""
import re
from dataclasses import dataclass
from pathlib import Path

SEP = "~"
VALUE = r"[^/~]+"   # a value holds neither separator, so a path splits back without ambiguity


@dataclass(frozen=True)
class Component:
    """One `name~value` directory. `field`: the attribute (or dict key) holding the value;
    `names`: what may stand before the `~` (alternatives when `choice`, the attribute holding the
    name chosen, is set); `columns`: the table column of each name, in the order of `names`."""
    field: str
    names: tuple
    columns: tuple
    choice: str = ""

    def __post_init__(self):
        if len(self.names) != len(self.columns) or (len(self.names) > 1) != bool(self.choice):
            raise ValueError(f"path component {self.field}: one column per name, a choice iff several")

    def name(self, fields):
        name = fields[self.choice] if self.choice else self.names[0]
        if name not in self.names:
            raise ValueError(f"path component {self.field}: '{name}' is not one of {self.names}")
        return name


SYSTEM = Component("system", ("system",), ("system",))
DIAMETER = Component("D", ("D",), ("D",))
# The table's `h` is the depth measured after settling; the path's is the depth asked for.
PLACEMENT = Component("pos", ("h", "z"), ("h_requested", "z_requested"), choice="place")
FRICTION = Component("mu", ("mu",), ("mu",))
STIFFNESS = Component("kn", ("kn",), ("kn",))
DAMPING = Component("gn", ("gn",), ("gamman",))
SEED = Component("seed", ("seed",), ("seed",))
SPEED = Component("value", ("Fr", "V"), ("Fr", "V"), choice="kind")

BED = (SYSTEM, DIAMETER, PLACEMENT, FRICTION, STIFFNESS, DAMPING, SEED)
# A placed system's column is poured once per seed without an intruder: a bed but D and placement.
COLUMN = tuple(c for c in BED if c not in (DIAMETER, PLACEMENT))
PULL = BED + (SPEED,)

# Path name -> table column, for every name a path may hold (what the run reader files a path under).
COLUMN_OF = {name: column for c in PULL for name, column in zip(c.names, c.columns)}


def _alternatives(texts):
    return "(?:" + "|".join(map(re.escape, texts)) + ")" if texts else "(?!)"


def pattern(components, **only):
    """The components as a regex without groups (a Snakemake wildcard constraint); `only`:
    field -> the values it may take (none: a pattern no path matches)."""
    parts = []
    for c in components:
        name = _alternatives(c.names) if c.choice else re.escape(c.names[0])
        value = _alternatives([str(v) for v in only[c.field]]) if c.field in only else VALUE
        parts.append(f"{name}{SEP}{value}")
    return "/".join(parts)


def regex(components):
    """The compiled regex of exactly these components, a named group per field (and choice)."""
    parts = []
    for c in components:
        name = f"(?P<{c.choice}>{'|'.join(map(re.escape, c.names))})" if c.choice else re.escape(c.names[0])
        parts.append(f"{name}{SEP}(?P<{c.field}>{VALUE})")
    return re.compile("^" + "/".join(parts) + "$")


def key(components, fields):
    """The path of `fields` (a mapping field -> text, choices included): the inverse of parse."""
    return "/".join(f"{c.name(fields)}{SEP}{fields[c.field]}" for c in components)


def parse(components, text):
    """{field: text} of a path of exactly these components; None if it is not one."""
    m = regex(components).match(text)
    return m.groupdict() if m else None


def part(name, value):
    """One component's directory: part('Fr', '1') is 'Fr~1'."""
    if name not in COLUMN_OF:
        raise ValueError(f"'{name}' is not a path component (known: {', '.join(COLUMN_OF)})")
    return f"{name}{SEP}{value}"


_ANY = re.compile("^(?P<name>" + "|".join(map(re.escape, COLUMN_OF)) + f"){SEP}(?P<value>{VALUE})$")


def name_of(directory):
    """The component name of one directory ('seed' for 'seed~2'), None for any other directory."""
    m = _ANY.match(directory)
    return m.group("name") if m else None


def named(path):
    """{name: text} of the components among a path's directories, wherever they stand (a run
    file moved out of the workflow's tree keeps what its path still says; the last wins)."""
    return {m.group("name"): m.group("value") for d in Path(path).parts if (m := _ANY.match(d))}
