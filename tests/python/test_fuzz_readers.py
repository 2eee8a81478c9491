"""The analysis package's readers under damaged input: run files (bit flips anywhere, bits
flipped inside each dataset's stored bytes, truncations), pull tables (cells, columns and
bytes mangled), fit files (JSON cut, keys removed, types swapped) and study configs (keys
removed, values of the wrong type or range). Each mutated input ends in the reader's own named
error (RunFileError, TableError, FitFileError, ConfigError) or in a valid read, never another
exception, and a run file damaged inside its data is always refused. Over 500 cases; the count
is printed.

The engine: $GRANUDRAG if set, else build/granudrag. A missing binary is a failure, not a skip.
"""
import copy
import json
import os
import random
import subprocess
from pathlib import Path

import h5py
import pytest
import synth
import yaml

from analysis.core.table import TableError, load_csv, write_csv
from analysis.fits.fit_file import FitFileError, load_fits
from analysis.fits.fitset import run_fits, save_results
from analysis.runs.runs import RunFileError, read_run
from granudrag_study.config import ConfigError, validate_config
from granudrag_study.plan import plan

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag"))
TALLY = {"cases": 0, "named": 0, "read": 0}


def outcome(read, named_error):
    """Runs read(); 'named' for the reader's own error with a message, 'read' for a valid read;
    any other exception fails the test with the case."""
    TALLY["cases"] += 1
    try:
        read()
    except named_error as exc:
        assert len(str(exc)) > 10
        TALLY["named"] += 1
        return "named"
    TALLY["read"] += 1
    return "read"


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    if not BINARY.is_file():
        pytest.fail(f"no granudrag binary at {BINARY}: build it (cmake --build build) or set $GRANUDRAG")
    d = tmp_path_factory.mktemp("fuzz")
    subprocess.run([str(BINARY), "pour", "--output", str(d / "bed.h5"), "--grains", "150", "--lx", "5",
                    "--ly", "4.5", "--intruder_diameter", "1.5", "--depth", "1.5", "--kn", "2e4",
                    "--max_settle_time", "0.5", "--quiet"], check=True, capture_output=True)
    run = d / "system~I" / "run.h5"
    run.parent.mkdir()
    subprocess.run([str(BINARY), "pull", "--bed", str(d / "bed.h5"), "--output", str(run), "--distance", "0.5",
                    "--quiet"], check=True, capture_output=True)
    read_run(run)  # valid as written
    return run


@pytest.mark.slow
def test_damaged_run_files_are_refused_by_name(run_file, tmp_path):
    data = run_file.read_bytes()
    rng = random.Random(7)
    damaged = tmp_path / "system~I" / "run.h5"
    damaged.parent.mkdir()
    # Anywhere in the file: headers, free space, data.
    for _ in range(150):
        b = bytearray(data)
        at = rng.randrange(len(b))
        b[at] ^= 1 << rng.randrange(8)
        damaged.write_bytes(bytes(b))
        outcome(lambda: read_run(damaged), RunFileError)
    for k in range(20):
        damaged.write_bytes(data[:len(data) * k // 20])
        assert outcome(lambda: read_run(damaged), RunFileError) == "named"
    # Inside the stored bytes of every dataset: h5py refuses to read the dataset (its checksum),
    # and the run reader, which takes its numbers mostly from attributes (covered by the object
    # headers' own checksums), still ends in its named error or a valid read.
    with h5py.File(run_file) as f:
        stored = []
        f.visititems(lambda name, obj: stored.append((name, obj.id.get_chunk_info(0)))
                     if isinstance(obj, h5py.Dataset) and obj.chunks and obj.id.get_num_chunks() else None)
    assert len(stored) > 20
    for name, chunk in stored:
        for _ in range(3):
            b = bytearray(data)
            b[chunk.byte_offset + rng.randrange(chunk.size)] ^= 1 << rng.randrange(8)
            damaged.write_bytes(bytes(b))
            with h5py.File(damaged) as f, pytest.raises(OSError):
                f[name][()]
            outcome(lambda: read_run(damaged), RunFileError)


def test_damaged_tables_are_refused_by_name(tmp_path):
    table = synth.make_table(seed=3).head(60)
    path = tmp_path / "table.csv"
    write_csv(table, path)
    text = path.read_text()
    lines = text.splitlines()
    rng = random.Random(11)
    garbage = ["abc", "", "nan", "-1", "1e400", "-inf", "0", "1,2", '"', "999999999999999999999"]
    damaged = tmp_path / "damaged.csv"
    for _ in range(120):
        kind = rng.randrange(5)
        if kind == 0:      # one cell
            row = rng.randrange(1, len(lines))
            cells = lines[row].split(",")
            cells[rng.randrange(len(cells))] = rng.choice(garbage)
            out = lines[:row] + [",".join(cells)] + lines[row + 1:]
        elif kind == 1:    # one column gone
            header = lines[0].split(",")
            c = rng.randrange(len(header))
            out = [",".join(x for i, x in enumerate(line.split(",")) if i != c) for line in lines]
        elif kind == 2:    # cut anywhere
            damaged.write_text(text[:rng.randrange(len(text))])
            outcome(lambda: load_csv(damaged), TableError)
            continue
        elif kind == 3:    # a header renamed
            header = lines[0].split(",")
            header[rng.randrange(len(header))] = "x" + str(rng.randrange(100))
            out = [",".join(header)] + lines[1:]
        else:              # bytes
            b = bytearray(text.encode())
            for _ in range(3):
                b[rng.randrange(len(b))] = rng.randrange(256)
            damaged.write_bytes(bytes(b))
            outcome(lambda: load_csv(damaged), TableError)
            continue
        damaged.write_text("\n".join(out) + "\n")
        outcome(lambda: load_csv(damaged), TableError)


def _paths(doc, prefix=()):
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield prefix + (k,)
            yield from _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:3]):
            yield prefix + (i,)
            yield from _paths(v, prefix + (i,))


def _at(doc, path):
    for p in path[:-1]:
        doc = doc[p]
    return doc, path[-1]


def test_damaged_fit_files_are_refused_by_name(tmp_path):
    table = synth.make_table(seed=2)
    path = tmp_path / "fits.json"
    save_results(path, run_fits(table, n_boot=10, seed=0))
    load_fits(path)
    text = path.read_text()
    doc = json.loads(text)
    paths = list(_paths(doc))
    rng = random.Random(5)
    damaged = tmp_path / "damaged.json"
    swaps = [None, "text", -1, 1e300, [], {}, True]
    for _ in range(140):
        kind = rng.randrange(3)
        if kind == 0:
            damaged.write_text(text[:rng.randrange(len(text))])
        else:
            d = copy.deepcopy(doc)
            parent, key = _at(d, rng.choice(paths))
            if kind == 1:
                del parent[key]
            else:
                parent[key] = rng.choice(swaps)
            damaged.write_text(json.dumps(d))
        outcome(lambda: load_fits(damaged), FitFileError)


@pytest.mark.slow
def test_damaged_study_configs_are_refused_by_name():
    base = yaml.safe_load((ROOT / "config" / "smoke.yaml").read_text())
    validate_config(base)
    plan(base)
    paths = list(_paths(base))
    rng = random.Random(3)
    swaps = [None, "text", -1, 0, 1e9, [], {}, True, [-1, "a"]]

    def check(cfg):
        validate_config(cfg)
        plan(cfg)

    for _ in range(140):
        cfg = copy.deepcopy(base)
        parent, key = _at(cfg, rng.choice(paths))
        if rng.randrange(3) == 0:
            del parent[key]
        else:
            parent[key] = rng.choice(swaps)
        outcome(lambda cfg=cfg: check(cfg), ConfigError)


@pytest.mark.slow   # it totals every fuzzer of the file, the slow ones too
def test_the_count(request):
    """Runs last in this file: the total over the readers."""
    print(f"\nfuzzed analysis readers: {TALLY['cases']} cases, {TALLY['named']} named errors, "
          f"{TALLY['read']} valid reads")
    assert TALLY["cases"] >= 500
