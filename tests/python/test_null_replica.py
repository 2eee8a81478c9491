"""tools/null_replica.py: a bed's copy with one mobile grain's velocity changed, written atomically."""
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "null_replica.py"


def fake_bed(path, species):
    with h5py.File(path, "w") as f:
        f.create_dataset("/particles/all/species/value", data=np.array(species, np.uint8), fletcher32=True, chunks=True)
        v = np.arange(3 * len(species), dtype=float).reshape(-1, 3)
        f.create_dataset("/particles/all/velocity/value", data=v, fletcher32=True, chunks=True)


def run(*args):
    return subprocess.run([sys.executable, str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_one_mobile_grains_x_velocity_changes_by_epsilon_and_nothing_else(tmp_path):
    bed, out = tmp_path / "bed.h5", tmp_path / "null.h5"
    fake_bed(bed, [1, 1, 0, 1, 1, 0, 0, 2])       # frozen base, mobile grains, an intruder
    r = run(bed, out, "--epsilon", "1e-6")
    assert r.returncode == 0, r.stderr
    assert "grain 5's x velocity + 1e-06" in r.stderr   # the middle is 4, frozen: the next mobile one
    with h5py.File(bed) as a, h5py.File(out) as b:
        va, vb = a["/particles/all/velocity/value"][()], b["/particles/all/velocity/value"][()]
    d = vb - va
    assert d[5, 0] == np.float64(15.0 + 1e-6) - 15.0 and np.count_nonzero(d) == 1
    assert not list(tmp_path.glob("*.tmp"))


def test_a_bed_without_a_mobile_grain_there_or_a_file_that_is_no_bed_is_refused(tmp_path):
    bed = tmp_path / "bed.h5"
    fake_bed(bed, [0, 1, 1, 1])
    r = run(bed, tmp_path / "out.h5")
    assert r.returncode == 2 and "no mobile grain at or after index 2; give a smaller --grain" in r.stderr
    assert run(bed, tmp_path / "out.h5", "--grain", "0").returncode == 0
    assert "bodies 0 to 3" in run(bed, tmp_path / "x.h5", "--grain", "9").stderr
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = 1
    r = run(other, tmp_path / "y.h5")
    assert r.returncode == 2 and "not a granudrag bed" in r.stderr
    assert not (tmp_path / "y.h5").exists() and not list(tmp_path.glob("*.tmp"))
