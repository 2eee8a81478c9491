"""A bed's XDMF sidecar as ParaView reads it, headless (pvbatch under xvfb-run), and the 3D
render of Fig. 1 made from it. tools/install-deps.sh installs ParaView and Xvfb."""
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from analysis.figures.headless import run_pvbatch

pytestmark = pytest.mark.slow   # ParaView's renders (tools/test.sh --quick leaves slow tests out)

ROOT = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag"))
RENDER = ROOT / "workflow" / "scripts" / "render_bed.py"


def pvbatch(*args):
    run = run_pvbatch(RENDER, *args, timeout=600)
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

    from analysis.report.report import figure_entries

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
    from analysis.report.report import figure_entries

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


def dumped_pull(tmp_path):
    """A short pull of the lattice bed with frames every 0.5 (4 frames after step 0)."""
    bed, per_type = lattice_bed(tmp_path)
    run = tmp_path / "run.h5"
    subprocess.run([str(BINARY), "pull", "--bed", str(bed), "--output", str(run), "--speed", "0.5",
                    "--distance", "1", "--dump_interval", "0.5", "--quiet"], check=True, capture_output=True)
    return run, per_type


def test_paraview_plays_a_dumped_pull_frame_by_frame(tmp_path):
    run, per_type = dumped_pull(tmp_path)
    with h5py.File(run) as f:
        times = f["particles/frames/position/time"][()]
        x = f["particles/frames/position/value"][()]
        species = f["particles/frames/species/value"][()]
    assert x.shape == (5, sum(per_type), 3)  # H5MD: the frame dimension leads
    seen = pvbatch("--check", f"{run}.xdmf")
    assert int(seen["frames"]) == len(times) == 5
    assert float(seen["first_time"]) == times[0] == 0.0
    assert abs(float(seen["last_time"]) - times[-1]) < 1e-9
    assert int(seen["first_points"]) == int(seen["last_points"]) == sum(per_type)
    assert "species" in seen["arrays"].split(",") and "velocity" in seen["arrays"].split(",")
    assert [int(c) for c in seen["species"].split(",")] == per_type
    # ParaView's last frame is the file's: the intruder has moved V t along x.
    intruder = int(np.flatnonzero(species == 2)[0])
    first = np.array([float(c) for c in seen["first_intruder"].split(",")])
    last = np.array([float(c) for c in seen["last_intruder"].split(",")])
    np.testing.assert_allclose(first, x[0, intruder], rtol=1e-5)
    np.testing.assert_allclose(last, x[-1, intruder], rtol=1e-5)
    assert abs(last[0] - first[0] - 0.5 * times[-1]) < 1e-4


def test_the_frames_of_a_pull_render_and_make_a_movie(tmp_path):
    import matplotlib.image

    run, _ = dumped_pull(tmp_path)
    frames = tmp_path / "frames"
    rendered = run_pvbatch(RENDER, "--frames", f"{run}.xdmf", frames, timeout=600)
    assert rendered.returncode == 0, rendered.stdout + rendered.stderr
    pngs = sorted(frames.glob("frame_*.png"))
    assert len(pngs) == 5
    first, last = (matplotlib.image.imread(p)[..., :3] for p in (pngs[0], pngs[-1]))
    assert float(np.var(first)) > 1e-3
    assert float(np.mean(np.abs(first - last))) > 1e-4  # the scene moves
    movie = tmp_path / "movie.mp4"
    subprocess.run(["/usr/bin/python3", str(ROOT / "workflow" / "scripts" / "movie.py"), f"{run}.xdmf",
                    str(movie), "10"], check=True, capture_output=True, timeout=600)
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                            "stream=nb_read_frames,codec_name", "-of", "csv=p=0", str(movie)],
                           check=True, capture_output=True, text=True).stdout.strip()
    assert probe == "h264,5"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".movie")] == []  # no leftovers


def test_the_movie_without_paraview_or_ffmpeg_says_what_to_install(tmp_path):
    empty = tmp_path / "bin"
    empty.mkdir()
    run = subprocess.run(["/usr/bin/python3", str(ROOT / "workflow" / "scripts" / "movie.py"), "x.xdmf",
                          str(tmp_path / "m.mp4")], capture_output=True, text=True,
                         env=dict(os.environ, PATH=str(empty)))
    assert run.returncode != 0
    assert "needs pvbatch and ffmpeg" in run.stderr and "tools/install-deps.sh" in run.stderr
    assert not (tmp_path / "m.mp4").exists()


def test_paraview_plays_a_dumped_pour(tmp_path):
    bed = tmp_path / "bed.h5"
    subprocess.run([str(BINARY), "pour", "--output", str(bed), "--lx", "6", "--ly", "6", "--grains", "300",
                    "--depth", "3", "--intruder_x", "3", "--intruder_y", "3", "--kn", "2e4", "--max_settle_time",
                    "3", "--dump_interval", "0.5", "--quiet"], check=True, capture_output=True)
    with h5py.File(bed) as f:
        times = f["particles/frames/position/time"][()]
        z = f["particles/frames/position/value"][:, :, 2]
    seen = pvbatch("--check", f"{bed}.frames.xdmf")
    assert int(seen["frames"]) == len(times) >= 7  # step 0, then every 0.5 up to t >= 3
    assert int(seen["first_points"]) == int(seen["last_points"]) == 301
    assert z[-1].mean() < z[0].mean()  # the grains fall


def test_a_render_that_lost_its_display_is_retried_after_a_growing_pause(monkeypatch):
    import analysis.figures.headless as headless

    outcomes = [(134, headless.LOST_DISPLAY), (134, headless.LOST_DISPLAY), (0, "")]
    calls, pauses = [], []

    def fake_run(cmd, **kw):
        calls.append(cmd)
        code, text = outcomes[len(calls) - 1]
        return subprocess.CompletedProcess(cmd, code, stdout=text, stderr="")

    monkeypatch.setattr(headless.subprocess, "run", fake_run)
    monkeypatch.setattr(headless.time, "sleep", pauses.append)
    assert headless.run_pvbatch("render.py", "x.xdmf").returncode == 0
    assert len(calls) == 3 and pauses == [headless.PAUSE, 2 * headless.PAUSE]
    # Any other failure is the render's own: returned at once, not retried.
    calls.clear()
    outcomes[:] = [(1, "vtkXdmfReader: no such file")]
    assert headless.run_pvbatch("render.py", "x.xdmf").returncode == 1 and len(calls) == 1


def test_a_bed_without_its_sidecar_is_named_not_rendered(tmp_path):
    # A bed restored from a rung's pieces has no .xdmf: Fig. 1 says so in one line rather than
    # quoting pvbatch's colour-coded errors into the report's caption.
    from analysis.figures.figures_bed import render_3d
    bed, _ = lattice_bed(tmp_path)
    Path(f"{bed}.xdmf").unlink()
    why = render_3d(bed, tmp_path / "a.png", RENDER)
    assert why.startswith("the bed's ParaView sidecar bed.h5.xdmf is missing") and "\x1b" not in why
    assert not (tmp_path / "a.png").exists()
