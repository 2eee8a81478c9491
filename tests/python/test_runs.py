"""analysis.runs.runs: run files (HDF5, the layout `granudrag pull` writes) into the tidy table."""
import math
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from analysis.core.table import froude, validate_table
from analysis.runs.runs import (
    RunFileError,
    load_runs,
    path_parameters,
    read_coordination_distribution,
    read_force_trace,
    read_parameters,
    read_run,
    read_snapshots,
)
from analysis.runs.series_error import mean_error
from analysis.validation.validation import SETTING_DEFAULTS

BED = "system~I/D~2/h~10/mu~0.5/kn~2e4/gn~199.05359/seed~1"
# The engine, for the test that reads what it writes: $GRANUDRAG, else build/granudrag.
BINARY = Path(os.environ.get("GRANUDRAG", Path(__file__).resolve().parents[2] / "build" / "granudrag"))


def write_parameters_v2(f):
    """/parameters as src/io/parameter_record.cpp writes it: one typed attribute per key with a
    value (strings fixed-length, flags h5py's bool enum, lists float64 arrays), units beside."""
    pour = f.create_group("parameters/pour")
    for key, value in {"output": np.bytes_(b"b.h5"), "lx": 10.0, "ly": 8.0, "grains": np.int64(1500),
                       "skin": 0.2, "quiet": np.bool_(True)}.items():
        pour.attrs[key] = value
    pour.create_group("units").attrs["lx"] = np.bytes_(b"d")
    pull = f.create_group("parameters/pull")
    for key, value in {"bed": np.bytes_(b"b.h5"), "output": np.bytes_(b"run.h5"), "speed": 1.0,
                       "distance": 2.7, "skin": 0.2, "snapshots": np.int64(3),
                       "resume": np.bool_(False)}.items():
        pull.attrs[key] = value


def write_parameters_v1(f):
    """/parameters as format version 1 wrote it: the pull's keys, then its bed's, as one YAML
    text (both have 'output' and 'skin')."""
    f.create_group("parameters").attrs["yaml"] = (
        "# pull\noutput: \"run.h5\"\nspeed: 1\ndistance: 2.7\nskin: 0.2\n"
        "# bed b.h5\noutput: \"b.h5\"\nlx: 10.0\nly: 8.0\ngrains: 1500\nintruder_x: ~\nskin: 0.2\n")


def write_run(path, D=2.0, depth=9.87, speed=0.75, mu=0.5, kn=2e4, gamman=199.05359,
              drag=111.1, fmt="granudrag-run", version=2, skip=None, n_samples=50,
              drag_err=2.5, convergence=(6.5, 1), verdict="clean"):
    """A run file with the attributes and datasets of src/io/run_file.cpp save_run."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(path, "w") as f:
        g = f.create_group("granudrag")
        g.attrs["format"] = fmt
        g.attrs["version"] = np.int64(version)
        (write_parameters_v1 if version == 1 else write_parameters_v2)(f)
        r = f.create_group("run")
        for k, v in dict(D=D, depth=depth, speed=speed, froude=float(froude(speed, D)), mu=mu,
                         kn=kn, gamman=gamman, dt=4.2e-4).items():
            r.attrs[k] = v
        r.attrs["steps"] = np.int64(6384)
        o = f.create_group("observables")
        t = np.arange(1, n_samples + 1) * 0.02
        fx = -drag + np.sin(t)
        force = np.column_stack([fx, np.zeros_like(t), np.ones_like(t)])
        o.create_dataset("intruder_force/time", data=t)
        o.create_dataset("intruder_force/value", data=force)
        o.create_dataset("intruder_force/step", data=np.arange(1, n_samples + 1) * 48)
        o.create_dataset("cumulative_drag/value", data=np.cumsum(-fx) / np.arange(1, n_samples + 1))
        conv = {} if convergence is None else dict(error_dof=convergence[0],
                                                   plateau=np.int64(convergence[1]))
        for name, attrs in {"drag": dict(value=drag, error=drag_err, transient_distance=0.5,
                                         transient_samples=np.int64(10 if skip is None else skip),
                                         **conv),
                            "coordination": dict(value=10.0, error=math.nan),
                            "theta": dict(value=1.55, error=0.1),
                            "bulk_coordination": dict(value=3.7, error=math.nan, shell=2.0),
                            "kappa": dict(value=0.96, error=math.nan)}.items():
            grp = o.require_group(name)
            for k, v in attrs.items():
                grp.attrs[k] = v
        o.create_dataset("bulk_coordination/distribution", data=np.full(16, 1 / 16))
        o.create_dataset("theta/histogram", data=np.zeros(36, dtype=np.int64))
        for k in range(2):      # as write_snapshots: /snapshots/<k>/{dx,dz,vx,vz}, attribute time
            s = f.create_group(f"snapshots/{k}")
            s.attrs["time"] = 1.0 + k
            for c, v in zip(("dx", "dz", "vx", "vz"), (1.0, -2.0, -speed, 0.1 * (k + 1))):
                s.create_dataset(c, data=np.full(3 + k, v))
        f.create_group("sanity").attrs["report"] = "sanity: grains lost 0"
        if verdict is not None:      # None: a file written before the verdict existed
            f["sanity"].attrs["verdict"] = verdict
    return path


def test_reads_one_run_with_path_parameters(tmp_path):
    p = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5")
    row = read_run(p, root=tmp_path)
    assert row["system"] == "I"
    assert row["h"] == pytest.approx(9.87) and row["h_requested"] == 10.0
    assert math.isnan(row["z_requested"])
    assert row["D"] == 2.0 and row["mu"] == 0.5 and row["kn"] == 2e4
    assert row["V"] == 0.75 and row["Fr"] == pytest.approx(1.0)
    # The drag as the engine stored it; its error recomputed from the force series after the
    # transient (analysis.runs.series_error), the engine's kept beside; the cumulative average of all
    assert row["drag"] == pytest.approx(111.1) and row["drag_err_engine"] == 2.5
    with h5py.File(p) as f:
        drag_t = -f["observables/intruder_force/value"][:, 0]
    assert row["drag_err"] == mean_error(drag_t[10:]).error and row["drag_dof"] == mean_error(drag_t[10:]).dof
    assert row["drag_cumulative"] == pytest.approx(drag_t.mean(), rel=1e-12)
    assert row["drag_cumulative_err"] == pytest.approx(row["drag_err"] * np.sqrt(40 / 50))
    assert row["n_contacts"] == 10.0 and row["theta"] == 1.55 and row["Z"] == 3.7
    assert row["kappa"] == 0.96
    assert row["run"] == f"pulls/{BED}/Fr~1"
    # The scale: box and grains from the bed's parameters, distance pulled from the run.
    assert (row["lx"], row["ly"], row["grains"]) == (10.0, 8.0, 1500.0)
    assert row["distance"] == pytest.approx(0.75 * 6384 * 4.2e-4)


@pytest.mark.parametrize("version", [1, 2])
def test_scale_is_nan_when_the_file_does_not_record_it(tmp_path, version):
    p = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5", version=version)
    with h5py.File(p, "a") as f:
        del f["parameters"]
    row = read_run(p)
    assert all(np.isnan(row[k]) for k in ("lx", "ly", "grains")) and row["drag"] > 0
    assert row["active_radius"] == 0.0 and row["asleep"] == 0.0   # a pull that records no region
    assert np.isnan(row["wake_force"]) and np.isnan(row["sleep_speed"])   # so no wake or rest test either
    assert np.isnan(row["wake_load"])
    assert np.isnan(row["sleep_time"])
    assert row["settle_damping"] == 0.0 and row["placed"] == 0.0     # nor its bed's pour or placement
    # A bed of format version 1, or imported: the run has no /parameters/pour.
    q = write_run(tmp_path / "pulls" / BED / "Fr~2" / "run.h5", speed=1.5)
    with h5py.File(q, "a") as f:
        del f["parameters/pour"]
        f["parameters"].attrs["pour_yaml_v1"] = "lx: 10.0\n"   # for people only: not read
    row = read_run(q)
    assert all(np.isnan(row[k]) for k in ("lx", "ly", "grains")) and row["drag"] > 0


def test_parameters_are_read_by_key_with_their_types(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5")
    params = read_parameters(p)
    assert set(params) == {"pour", "pull"}
    assert params["pour"] == {"output": "b.h5", "lx": 10.0, "ly": 8.0, "grains": 1500, "skin": 0.2,
                              "quiet": True}
    assert params["pull"]["speed"] == 1.0 and params["pull"]["bed"] == "b.h5"
    assert params["pull"]["resume"] is False and params["pull"]["snapshots"] == 3
    assert type(params["pour"]["grains"]) is int
    with h5py.File(p, "a") as f:
        f["parameters/pull"].attrs["speeds"] = np.array([0.1, 1.0])
    assert read_parameters(p)["pull"]["speeds"] == [0.1, 1.0]


def test_old_version_run_files_are_read_through_the_legacy_path(tmp_path):
    p = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5", version=1)
    row = read_run(p, root=tmp_path)
    assert (row["lx"], row["ly"], row["grains"]) == (10.0, 8.0, 1500.0)
    assert row["drag"] == pytest.approx(111.1)
    assert load_runs([p]).drag.tolist() == [pytest.approx(111.1)]
    with pytest.raises(RunFileError, match="version 1 records its parameters as text.*re-run the pull"):
        read_parameters(p)
    # A version 2 file is never read through the text, even if one is there.
    q = write_run(tmp_path / "pulls" / BED / "Fr~2" / "run.h5", speed=1.5)
    with h5py.File(q, "a") as f:
        f["parameters"].attrs["yaml"] = "lx: 99.0\n"
    assert read_run(q)["lx"] == 10.0


def test_bad_parameters_are_refused_by_name(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5")
    with h5py.File(p, "a") as f:
        f["parameters/pour"].attrs["lx"] = np.bytes_(b"wide")
    with pytest.raises(RunFileError, match="/parameters/pour attribute 'lx' is not a number"):
        read_run(p)
    with h5py.File(p, "a") as f:
        del f["parameters/pull"]
    with pytest.raises(RunFileError, match="no /parameters/pull"):
        read_parameters(p)
    with h5py.File(p, "a") as f:
        del f["parameters"]
    with pytest.raises(RunFileError, match="no group /parameters"):
        read_parameters(p)


@pytest.mark.parametrize("content, message", [
    (b"system,D\nI,2\n", "not an HDF5 file"),
    (b"\x89HDF\r\n\x1a\n" + b"\x00" * 40, "unreadable HDF5 file"),
])
def test_read_parameters_refuses_foreign_and_corrupt_files(tmp_path, content, message):
    p = tmp_path / "run.h5"
    p.write_bytes(content)
    with pytest.raises(RunFileError, match=message):
        read_parameters(p)
    bed = write_run(tmp_path / "bed.h5", fmt="granudrag-bed")
    with pytest.raises(RunFileError, match="'granudrag-bed' file"):
        read_parameters(bed)
    newer = write_run(tmp_path / "new.h5", version=7)
    with pytest.raises(RunFileError, match="version 7 is not supported"):
        read_parameters(newer)


def test_the_engine_writes_what_the_reader_reads(tmp_path):
    """A real pour and pull: every key comes back with its type, and the table's scale."""
    subprocess.run([str(BINARY), "pour", "--output", str(tmp_path / "bed.h5"), "--grains", "150",
                    "--lx", "5", "--ly", "4.5", "--intruder_diameter", "1.5", "--depth", "1.5",
                    "--kn", "2e4", "--max_settle_time", "0.5", "--settle_damping", "0.5", "--quiet"],
                   check=True, capture_output=True)
    run = tmp_path / "system~I" / "run.h5"
    run.parent.mkdir()
    subprocess.run([str(BINARY), "pull", "--bed", str(tmp_path / "bed.h5"), "--output", str(run),
                    "--distance", "0.5", "--active_radius", "3", "--quiet"], check=True, capture_output=True)
    params = read_parameters(run)
    assert params["pour"]["grains"] == 150 and params["pour"]["lx"] == 5.0
    assert params["pour"]["quiet"] is True and "intruder_z" not in params["pour"]   # unset: absent
    assert params["pull"]["bed"] == str(tmp_path / "bed.h5") and params["pull"]["distance"] == 0.5
    assert params["pull"]["resume"] is False and params["pull"]["snapshots"] == 3
    row = read_run(run)
    assert (row["lx"], row["ly"], row["grains"]) == (5.0, 4.5, 150.0)
    assert row["active_radius"] == 3.0       # the validation of the active region compares by it
    # The default wake and rest tests, recorded (each setting tells variants apart), and the defaults
    # the validation's labels leave out are the engine's
    assert ((row["wake_force"], row["wake_load"], row["sleep_speed"], row["sleep_time"]) ==
            (SETTING_DEFAULTS["wake_force"], SETTING_DEFAULTS["wake_load"], SETTING_DEFAULTS["sleep_speed"],
             SETTING_DEFAULTS["sleep_time"]))
    # An unset wake_force follows the bed's K_n: not a recorded key, the value used beside the count
    assert "wake_force" not in params["pull"]
    with h5py.File(run) as f:
        assert f["observables/sleeping_grains"].attrs["wake_force"] == 0.5
    assert row["perturbation"] == 0.0
    assert row["settle_damping"] == 0.5      # the bed's, which its validation compares by
    # The radius in intruder diameters (D = 1.5), and a replica: read as the radius in d.
    replica = tmp_path / "system~R" / "run.h5"
    replica.parent.mkdir()
    subprocess.run([str(BINARY), "pull", "--bed", str(tmp_path / "bed.h5"), "--output", str(replica),
                    "--distance", "0.5", "--active_diameters", "2", "--perturbation", "1e-9", "--wake_force", "1",
                    "--sleep_speed", "0.002", "--sleep_time", "0.5", "--wake_load", "0.2", "--quiet"],
                   check=True, capture_output=True)
    again = read_run(replica)
    assert again["active_radius"] == 3.0 and again["perturbation"] == 1e-9 and again["wake_force"] == 1.0
    assert again["sleep_speed"] == 0.002 and again["sleep_time"] == 0.5 and again["wake_load"] == 0.2
    assert read_parameters(replica)["pull"]["active_diameters"] == 2.0
    # A file from before the value used was recorded: the key it was given
    with h5py.File(replica, "r+") as f:
        assert f["observables/sleeping_grains"].attrs["wake_force"] == 1.0
        del f["observables/sleeping_grains"].attrs["wake_force"]
    assert read_run(replica)["wake_force"] == 1.0
    with h5py.File(run) as f:
        counts = f["observables/sleeping_grains/value"][()]
    assert row["asleep"] == pytest.approx(counts.mean() / 150) and 0 <= row["asleep"] <= 1
    assert row["sanity"] == "clean"
    # The drag error's Student-t dof and convergence flag: a 0.5 d pull is far too short.
    assert row["drag_dof"] >= 1 and row["plateau"] is False


def test_drag_error_convergence_and_seed_are_read(tmp_path):
    # The engine's convergence flag is kept as plateau_engine; drag_dof and plateau are the
    # force series' own (analysis.runs.series_error: 40 samples of a slow sine do not converge).
    p = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5", convergence=(3.2, 0))
    row = read_run(p, root=tmp_path)
    assert row["plateau_engine"] is False and row["seed"] == 1.0
    with h5py.File(p) as f:
        own = mean_error(-f["observables/intruder_force/value"][10:, 0])
    assert (row["drag_dof"], row["plateau"]) == (own.dof, own.plateau) and row["plateau"] is False
    p = write_run(tmp_path / "b" / "system~I" / "run.h5", convergence=(40.0, 1))
    row = read_run(p)
    assert row["plateau_engine"] is True and math.isnan(row["seed"])
    # A file from before the convergence test claims no plateau.
    p = write_run(tmp_path / "c" / "system~I" / "run.h5", convergence=None)
    assert read_run(p)["plateau_engine"] is False


def test_load_runs_gives_a_valid_table(tmp_path):
    paths = [write_run(tmp_path / "pulls" / BED / f"Fr~{fr:g}" / "run.h5",
                       speed=float(fr) * 0.75, drag=100 + fr) for fr in (0.5, 1, 2)]
    paths.append(write_run(tmp_path / "pulls" / BED / "V~0.01" / "run.h5", speed=0.01, drag=50))
    df = load_runs(paths, root=tmp_path)
    validate_table(df)
    assert len(df) == 4
    assert list(df.drag) == [100.5, 101, 102, 50]
    assert (df.system == "I").all() and df.run.is_unique


def test_depth_without_h_component_has_no_requested_depth(tmp_path):
    p = write_run(tmp_path / "somewhere" / "run.h5", depth=24.6)
    row = read_run(p, system="I")
    assert row["h"] == pytest.approx(24.6) and math.isnan(row["h_requested"])


def test_a_bed_placed_by_height_keeps_its_requested_height(tmp_path):
    # faithful.yaml's systems place the intruder at a height (z~): a validation study through
    # such beds tells its points apart by it.
    bed = BED.replace("h~10", "z~13.5")
    row = read_run(write_run(tmp_path / "pulls" / bed / "Fr~1" / "run.h5", depth=23.0), root=tmp_path)
    assert row["z_requested"] == 13.5 and math.isnan(row["h_requested"])
    assert row["h"] == pytest.approx(23.0)


def test_system_is_required(tmp_path):
    p = write_run(tmp_path / "run.h5")
    with pytest.raises(RunFileError, match="no system given"):
        read_run(p)
    assert read_run(p, system="II")["system"] == "II"


@pytest.mark.parametrize("content, message", [
    (b"system,D\nI,2\n", "not an HDF5 file"),
    (b"\x89HDF\r\n\x1a\n" + b"\x00" * 40, "unreadable HDF5 file"),
])
def test_foreign_and_corrupt_files_are_refused(tmp_path, content, message):
    p = tmp_path / "system~I" / "run.h5"
    p.parent.mkdir()
    p.write_bytes(content)
    with pytest.raises(RunFileError, match=message) as exc:
        read_run(p)
    assert str(p) in str(exc.value)


def test_truncated_run_file_is_refused(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5")
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 3])
    with pytest.raises(RunFileError, match=str(p)):
        read_run(p)


def test_other_granudrag_files_are_refused(tmp_path):
    bed = write_run(tmp_path / "system~I" / "bed.h5", fmt="granudrag-bed")
    with pytest.raises(RunFileError, match="'granudrag-bed' file.*pull it"):
        read_run(bed)
    newer = write_run(tmp_path / "system~I" / "new.h5", version=7)
    with pytest.raises(RunFileError, match="version 7 is not supported"):
        read_run(newer)
    plain = tmp_path / "system~I" / "plain.h5"
    with h5py.File(plain, "w") as f:
        f.create_dataset("x", data=[1, 2])
    with pytest.raises(RunFileError, match="not a granudrag file"):
        read_run(plain)


def test_missing_attribute_is_named(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5")
    with h5py.File(p, "a") as f:
        del f["run"].attrs["speed"]
    with pytest.raises(RunFileError, match="no attribute 'speed' on /run"):
        read_run(p)
    with h5py.File(p, "a") as f:
        f["run"].attrs["speed"] = 0.75
        del f["observables/theta"]
    with pytest.raises(RunFileError, match="no group theta"):
        read_run(p)


def test_run_in_the_wrong_place_is_refused(tmp_path):
    p = write_run(tmp_path / "pulls" / BED.replace("mu~0.5", "mu~0.3") / "Fr~1" / "run.h5")
    with pytest.raises(RunFileError, match="path says mu = 0.3 but the file has mu = 0.5"):
        read_run(p)
    q = write_run(tmp_path / "pulls" / BED / "Fr~2" / "run.h5")
    with pytest.raises(RunFileError, match="path says Fr = 2"):
        read_run(q)
    # Names that the table calls otherwise (analysis.core.path_scheme): gn is gamman, V the speed.
    r = write_run(tmp_path / "pulls" / BED.replace("gn~199.05359", "gn~200") / "Fr~1" / "run.h5")
    with pytest.raises(RunFileError, match="path says gn = 200 but the file has gamman = 199.054"):
        read_run(r)
    with pytest.raises(RunFileError, match="path says V = 0.5 but the file has speed = 0.75"):
        read_run(write_run(tmp_path / "pulls" / BED / "V~0.5" / "run.h5"))
    with pytest.raises(RunFileError, match="path component 'h~ten' is not a number"):
        read_run(write_run(tmp_path / "pulls" / BED.replace("h~10", "h~ten") / "Fr~1" / "run.h5"))


def test_a_bed_placed_by_height_gives_its_requested_height_and_no_depth(tmp_path):
    p = write_run(tmp_path / "pulls" / BED.replace("h~10", "z~13.5") / "V~0.75" / "run.h5")
    row = read_run(p)
    assert row["z_requested"] == 13.5 and math.isnan(row["h_requested"]) and row["seed"] == 1.0
    assert row["h"] == pytest.approx(9.87) and row["V"] == 0.75   # the table's h: measured, from the file


def test_failed_pull_without_drag_is_refused(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5", drag=math.nan)
    with pytest.raises(RunFileError, match="produced no drag"):
        read_run(p)


def test_missing_and_bad_files_are_listed_by_name(tmp_path):
    good = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5")
    missing = tmp_path / "pulls" / BED / "Fr~3" / "run.h5"
    bad = tmp_path / "pulls" / BED / "Fr~4" / "run.h5"
    bad.parent.mkdir(parents=True)
    bad.write_text("not a run")
    with pytest.raises(RunFileError) as exc:
        load_runs([good, missing, bad])
    text = str(exc.value)
    assert "2 of 3 run files unusable" in text
    assert f"{missing}: no such file" in text and f"{bad}: not an HDF5 file" in text
    df, problems = load_runs([good, missing, bad], errors="collect")
    assert len(df) == 1 and len(problems) == 2


def test_empty_list_gives_an_empty_table():
    df = load_runs([])
    assert df.empty and "drag" in df.columns


def test_force_trace(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5", drag=80.0, skip=10)
    t, drag, transient = read_force_trace(p)
    assert len(t) == len(drag) == 50
    assert transient == pytest.approx(t[9])
    assert np.mean(drag) == pytest.approx(80.0, abs=1.0)


def test_path_parameters():
    assert path_parameters(f"results/pulls/{BED}/V~0.01/run.h5") == {
        "system": "I", "D": "2", "h": "10", "mu": "0.5", "kn": "2e4", "gn": "199.05359",
        "seed": "1", "V": "0.01"}


def test_coordination_distribution_and_snapshots(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5", speed=0.75)
    z, pz = read_coordination_distribution(p)
    assert list(z) == list(range(16)) and pz.sum() == pytest.approx(1.0)
    snaps = read_snapshots(p)
    assert [s.attrs["time"] for s in snaps] == [1.0, 2.0]
    assert [len(s) for s in snaps] == [3, 4]
    assert np.allclose(snaps[1].vx, -0.75) and np.allclose(snaps[1].vz, 0.2)
    with h5py.File(p, "a") as f:
        f["observables/bulk_coordination/distribution"][3] = np.nan
    with pytest.raises(RunFileError, match="P\\(Z\\)"):
        read_coordination_distribution(p)
    text = tmp_path / "system~I" / "x.h5"
    text.write_text("not hdf5")
    with pytest.raises(RunFileError, match="not an HDF5 file"):
        read_snapshots(text)


def test_a_run_whose_verdict_is_not_clean_is_left_out_by_name(tmp_path):
    good = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5")
    old = write_run(tmp_path / "pulls" / BED / "Fr~2" / "run.h5", speed=1.5, verdict=None)
    bad = write_run(tmp_path / "pulls" / BED / "Fr~3" / "run.h5", speed=2.25,
                    verdict="overlap 0.1541 d at t = 0.08057 exceeds max_overlap = 0.15 d")
    assert read_run(good)["sanity"] == "clean"
    assert read_run(old)["sanity"] == "unknown"      # before the verdict: read, marked unknown
    with pytest.raises(RunFileError, match="sanity verdict is not clean.*exceeds max_overlap"):
        read_run(bad)
    df, problems = load_runs([good, old, bad], errors="collect")
    assert list(df.sanity) == ["clean", "unknown"]
    assert len(problems) == 1 and problems[0].startswith(f"{bad}: sanity verdict is not clean")


def test_the_engine_records_a_failed_verdict_and_the_table_leaves_the_run_out(tmp_path):
    """A real pull that breaks its overlap bound: without --keep_going it stops (exit 1, no run
    file); with it, it finishes and records the failure, and load_runs lists it by name."""
    bed = tmp_path / "bed.h5"
    subprocess.run([str(BINARY), "pour", "--output", str(bed), "--grains", "150", "--lx", "5", "--ly", "4.5",
                    "--intruder_diameter", "1.5", "--depth", "1.5", "--kn", "2e4", "--max_settle_time", "0.5",
                    "--quiet"], check=True, capture_output=True)
    run = tmp_path / "system~I" / "run.h5"
    run.parent.mkdir()
    # Grains still settling overlap by ~0.01-0.03 d at kn = 2e4: over a 0.005 d bound, already
    # in the bed as poured, which is refused before the first step.
    pull = [str(BINARY), "pull", "--bed", str(bed), "--output", str(run), "--distance", "0.1",
            "--speed", "0.1", "--max_overlap", "0.005", "--quiet"]
    r = subprocess.run(pull, capture_output=True, text=True)
    assert r.returncode == 1 and "beyond 'max_overlap' = 0.005 d" in r.stderr, r.stderr
    assert not run.exists()
    subprocess.run([*pull, "--keep_going"], check=True, capture_output=True)
    df, problems = load_runs([run], errors="collect")
    assert df.empty
    assert len(problems) == 1 and problems[0].startswith(f"{run}: sanity verdict is not clean")
    assert "exceeds max_overlap = 0.005 d" in problems[0]


def test_kappa_error_from_the_coordination_series(tmp_path):
    # kappa = (Z/n)(D+d)^2/(2 sqrt 3): its error is kappa times the relative error of n. Files
    # without the engine's error of n: block averaging of the intruder_contacts series after
    # the transient (0.5 d at V = 0.75: t > 0.667). White noise of standard deviation 2 about
    # n = 10 over 1000 samples: the analytic standard error of the mean is 2/sqrt(N); block
    # averaging's largest level lands within [0.8, 1.6] of it.
    p = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5")
    assert math.isnan(read_run(p)["kappa_err"])          # no series: no error
    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 20.0, 1034)
    with h5py.File(p, "a") as f:
        f["observables/intruder_contacts/time"] = t
        f["observables/intruder_contacts/value"] = 10.0 + 2.0 * rng.standard_normal(len(t))
    n_after = int(np.sum(t > 0.5 / 0.75))
    row = read_run(p)
    expected = 0.96 * (2.0 / np.sqrt(n_after)) / 10.0
    assert 0.8 < row["kappa_err"] / expected < 1.6, row["kappa_err"] / expected
    # The engine's own error of n (the drag's estimator), when the file has it, is used
    # instead of block averaging: kappa_err = kappa * n_err / n exactly.
    with h5py.File(p, "a") as f:
        f["observables/coordination"].attrs["error"] = 0.05
    assert read_run(p)["kappa_err"] == pytest.approx(0.96 * 0.05 / 10.0, rel=1e-12)

