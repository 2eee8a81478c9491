"""Render a bed (its .xdmf sidecar) in 3D with ParaView, headless: grains as spheres sized by
radius, coloured by species (mobile grain, frozen base, intruder); or every frame of a pull
run with --dump_interval (its temporal .xdmf sidecar), for a movie.

Run with ParaView's own interpreter, offscreen or under a virtual X server:

    pvbatch --force-offscreen-rendering workflow/scripts/render_bed.py BED.h5.xdmf OUT.png
    xvfb-run -a pvbatch workflow/scripts/render_bed.py BED.h5.xdmf OUT.png
    xvfb-run -a pvbatch workflow/scripts/render_bed.py --frames RUN.h5.xdmf OUTDIR

--frames writes OUTDIR/frame_00000.png, ... one per frame, the camera fixed on the first.
With --check it only prints what ParaView reads (frames, points, arrays, species counts; for a
temporal sidecar, of the first and the last frame), one `key value` line each, for tests.
"""

import os
import sys

from paraview import servermanager
from paraview.simple import (
    Clip,
    ColorBy,
    GetActiveViewOrCreate,
    GetColorTransferFunction,
    Glyph,
    Render,
    ResetCamera,
    SaveScreenshot,
    Show,
    XDMFReader,
)

# ParaView's Xdmf3 readers refuse these sidecars; its XDMF reader reads them as written.


def open_bed(path):
    reader = XDMFReader(FileNames=[path])
    reader.UpdatePipeline()
    return reader


def first_block(data):
    while data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    return data


def check(path):
    reader = open_bed(path)
    times = list(reader.TimestepValues or [])
    print("frames", len(times))
    if times:
        for name, t in (("first", times[0]), ("last", times[-1])):
            reader.UpdatePipeline(t)
            block = first_block(servermanager.Fetch(reader))
            print(f"{name}_time", t)
            print(f"{name}_points", block.GetNumberOfPoints())
            intruder = intruder_points(block)
            if intruder:
                print(f"{name}_intruder", ",".join(f"{c:.6g}" for c in block.GetPoint(intruder[0])))
    block = first_block(servermanager.Fetch(reader))
    point_data = block.GetPointData()
    print("points", block.GetNumberOfPoints())
    print("arrays", ",".join(point_data.GetArrayName(i) for i in range(point_data.GetNumberOfArrays())))
    species = point_data.GetArray("species")
    if species is not None:
        counts = [0, 0, 0]
        for i in range(species.GetNumberOfTuples()):
            counts[int(species.GetTuple1(i))] += 1
        print("species", ",".join(str(c) for c in counts))


def intruder_points(block):
    species = block.GetPointData().GetArray("species")
    if species is None:
        return []
    return [i for i in range(block.GetNumberOfPoints()) if int(species.GetTuple1(i)) == 2]


def scene(path, size):
    """The bed (or the run's frames) at `path` shown in a render view; returns reader, view."""
    reader = open_bed(path)
    # As in the paper's Fig. 1: the half of the bed in front of the intruder's plane (y less than
    # the intruder's y) is cut away, whole grains at a time, so the intruder shows.
    block = first_block(servermanager.Fetch(reader))
    intruder = intruder_points(block)
    source = reader
    if intruder:
        cut = Clip(Input=reader)
        cut.ClipType = "Plane"
        cut.ClipType.Origin = list(block.GetPoint(intruder[0]))
        cut.ClipType.Normal = [0.0, 1.0, 0.0]
        cut.Crinkleclip = 1
        cut.Invert = 0
        source = cut
    # Sphere glyphs scaled by the radius array: a glyph of scale 2 r has radius r.
    glyph = Glyph(Input=source, GlyphType="Sphere")
    glyph.ScaleArray = ["POINTS", "radius"]
    glyph.ScaleFactor = 2.0
    glyph.GlyphMode = "All Points"
    glyph.GlyphType.ThetaResolution = 12
    glyph.GlyphType.PhiResolution = 12
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = list(size)
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.OrientationAxesVisibility = 0
    display = Show(glyph, view)
    ColorBy(display, ("POINTS", "species"))
    lut = GetColorTransferFunction("species")
    # 0 mobile: sand, 1 frozen base: grey, 2 intruder: red.
    lut.InterpretValuesAsCategories = 1
    lut.Annotations = ["0", "mobile", "1", "frozen base", "2", "intruder"]
    lut.IndexedColors = [0.85, 0.75, 0.55, 0.45, 0.45, 0.45, 0.85, 0.1, 0.1]
    display.SetScalarBarVisibility(view, False)
    view.CameraPosition = [1.0, -2.2, 1.2]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    ResetCamera(view)
    return reader, view


def render(path, out, size=(1200, 800)):
    _, view = scene(path, size)
    Render(view)
    SaveScreenshot(out, view, ImageResolution=list(size))


def render_frames(path, out_dir, size=(1280, 720)):
    """Every frame of a run's temporal sidecar, as out_dir/frame_00000.png, ...; the camera
    stays where the first frame put it."""
    reader, view = scene(path, size)
    os.makedirs(out_dir, exist_ok=True)
    times = list(reader.TimestepValues or [])
    if not times:
        sys.exit(f"{path} has no frames: pull with --dump_interval to write them")
    for k, t in enumerate(times):
        view.ViewTime = t
        Render(view)
        SaveScreenshot(os.path.join(out_dir, f"frame_{k:05d}.png"), view, ImageResolution=list(size))
    print("frames", len(times))


def main(argv):
    if len(argv) == 3 and argv[1] == "--check":
        check(argv[2])
    elif len(argv) == 4 and argv[1] == "--frames":
        render_frames(argv[2], argv[3])
    elif len(argv) == 3:
        render(argv[1], argv[2])
    else:
        sys.exit("usage: pvbatch render_bed.py [--check] BED.h5.xdmf [OUT.png] | --frames RUN.h5.xdmf OUTDIR")


main(sys.argv)
