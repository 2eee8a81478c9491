"""A bed's XDMF sidecar as ParaView reads it, headless (pvbatch under xvfb-run), and the 3D
render of Fig. 1 made from it. tools/install-deps.sh installs ParaView and Xvfb."""
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag"))
RENDER = ROOT / "workflow" / "scripts" / "render_bed.py"


def pvbatch(*args):
    run = subprocess.run(["xvfb-run", "-a", "pvbatch", str(RENDER), *map(str, args)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    return dict(line.split(" ", 1) for line in run.stdout.splitlines() if " " in line)


def lattice_bed(tmp_path):
    """A LAMMPS data file of a small loose lattice (type 1 grains, a type 2 base layer, one
    type 3 intruder), imported into a bed with its sidecar."""
    intruder = np.array([3.0, 3.0, 4.1])
    atoms = []
    for k in range(12):
        for j in range(5):
            for i in range(5):
                x = np.array([0.6 + 1.2 * i, 0.6 + 1.2 * j, 0.5 + 1.2 * k])
                if np.linalg.norm(x - intruder) > 1.55:
                    atoms.append((2 if k == 0 else 1, 1.0, *x))
    atoms.append((3, 2.0, *intruder))
    lines = ["granudrag test bed", "", f"{len(atoms)} atoms", "3 atom types", "",
             "0 6 xlo xhi", "0 6 ylo yhi", "0 16 zlo zhi", "", "Atoms # sphere", ""]
    lines += [f"{n + 1} {t} {d} 1 {x} {y} {z}" for n, (t, d, x, y, z) in enumerate(atoms)]
    data = tmp_path / "bed.data"
    data.write_text("\n".join(lines) + "\n")
    bed = tmp_path / "bed.h5"
    subprocess.run([str(BINARY), "import-lammps", "--data", str(data), "--output", str(bed)],
                   check=True, capture_output=True)
    return bed, [sum(a[0] == t for a in atoms) for t in (1, 2, 3)]


def test_paraview_reads_a_beds_sidecar_with_its_species(tmp_path):
    bed, per_type = lattice_bed(tmp_path)
    seen = pvbatch("--check", str(bed) + ".xdmf")
    assert int(seen["points"]) == sum(per_type)
    assert "species" in seen["arrays"].split(",")
    assert "radius" in seen["arrays"].split(",")
    with h5py.File(bed) as f:
        species = f["particles/all/species/value"][()]
    expected = [int(np.sum(species == s)) for s in range(3)]
    assert expected == per_type  # LAMMPS types 1, 2, 3: mobile, frozen base, intruder
    assert [int(c) for c in seen["species"].split(",")] == expected


def test_the_3d_render_of_a_bed_is_a_picture(tmp_path):
    import matplotlib.image

    bed, _ = lattice_bed(tmp_path)
    out = tmp_path / "bed.png"
    pvbatch(str(bed) + ".xdmf", out)
    image = matplotlib.image.imread(out)[..., :3]
    assert image.shape[0] > 100 and image.shape[1] > 100
    assert float(np.var(image)) > 1e-3
    # The intruder (red: species 2) is in view, not hidden behind the grains in front of it.
    red = (image[..., 0] > 0.6) & (image[..., 1] < 0.3) & (image[..., 2] < 0.3)
    assert red.sum() > 50


FIG1 = ROOT / "workflow" / "scripts" / "fig1.py"


def test_fig1_draws_all_panels_and_the_report_lists_it_first(tmp_path):
    import matplotlib.image

    from analysis.report import figure_entries

    bed, _ = lattice_bed(tmp_path)
    out = tmp_path / "fig01_beds.png"
    subprocess.run(["/usr/bin/python3", str(FIG1), str(out), str(bed), str(bed)], check=True,
                   capture_output=True, timeout=900)
    assert out.with_suffix(".pdf").is_file()
    assert out.with_suffix(".txt").read_text().strip() == ""
    image = matplotlib.image.imread(out)[..., :3]
    assert float(np.var(image)) > 1e-3
    caption, png, why = figure_entries(tmp_path)[0]
    assert caption.startswith("Fig. 1") and png == out and why == ""


def test_fig1_without_paraview_says_which_panels_are_missing(tmp_path):
    from analysis.report import figure_entries

    bed, _ = lattice_bed(tmp_path)
    out = tmp_path / "fig01_beds.png"
    empty = tmp_path / "bin"
    empty.mkdir()
    env = dict(os.environ, PATH=str(empty))  # no pvbatch, no xvfb-run
    subprocess.run(["/usr/bin/python3", str(FIG1), str(out), str(bed)], check=True,
                   capture_output=True, env=env, timeout=600)
    note = out.with_suffix(".txt").read_text()
    assert "Panel (a) is missing: ParaView (pvbatch) is not installed" in note
    assert "Panel (c) is missing: the study has no such bed" in note
    assert "(b)" not in note
    caption, png, _ = figure_entries(tmp_path)[0]
    assert png == out and "Panel (a) is missing" in caption
