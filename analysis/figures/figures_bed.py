"""Fig. 1: (a) and (c) 3D views of a system I and a system II bed with the intruder, rendered
headless by ParaView (the workflow's render_bed.py under pvbatch), and (b) the slice through
the intruder's plane of the system I bed (grains as circles sized by radius, the intruder
highlighted), drawn with matplotlib.

Without ParaView the 3D panels are drawn as notes saying so, and <out>.txt names the missing
panels (the report adds it to the caption); the study does not fail.
"""

import re
import shutil
import tempfile
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from .headless import run_pvbatch  # noqa: E402

COLOURS = {0: "#d9bf8c", 1: "#737373", 2: "#d91a1a"}
ANSI = re.compile(r"\x1b\[[0-9;]*m")   # the colour codes of VTK's log lines


def render_3d(bed, png, render_script):
    """Renders bed's sidecar into png with render_script under pvbatch; returns None, or why
    it could not."""
    if shutil.which("pvbatch") is None:
        return "ParaView (pvbatch) is not installed"
    if not Path(f"{bed}.xdmf").is_file():
        # A bed copied without its sidecar (tools/rung-pieces.sh keeps bed.h5 only): granudrag
        # pour writes it; pvbatch would fail on it with a page of colour-coded errors.
        return f"the bed's ParaView sidecar {Path(bed).name}.xdmf is missing beside it (pour the bed again to write it)"
    run = run_pvbatch(render_script, f"{bed}.xdmf", png)
    if run.returncode == 0 and Path(png).is_file():
        return None
    lines = [ANSI.sub("", x).strip() for x in (run.stderr + run.stdout).strip().splitlines()]
    said = [x for x in lines if "what()" in x or "ERR|" in x or "rror" in x] or lines[-3:]
    return "pvbatch failed: " + " ".join(said[:1])[:300]


def slice_panel(ax, bed):
    """The grains the plane y = y_intruder cuts, as circles of their cut radius (x, z)."""
    with h5py.File(bed, "r") as f:
        x = f["particles/all/position/value"][()]
        r = f["particles/all/radius/value"][()]
        species = f["particles/all/species/value"][()]
    intruders = np.flatnonzero(species == 2)
    y0 = x[intruders[0], 1] if intruders.size else np.median(x[:, 1])
    dy = x[:, 1] - y0
    cut = np.abs(dy) < r
    patches, colours = [], []
    for i in np.flatnonzero(cut):
        patches.append(Circle((x[i, 0], x[i, 2]), np.sqrt(r[i] ** 2 - dy[i] ** 2)))
        colours.append(COLOURS[int(species[i])])
    ax.add_collection(PatchCollection(patches, facecolors=colours, edgecolors="k", linewidths=0.3))
    ax.set_xlim(x[:, 0].min() - 1, x[:, 0].max() + 1)
    ax.set_ylim(min(0.0, x[:, 2].min() - 1), x[:, 2].max() + 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x / d")
    ax.set_ylabel("z / d")


def note_panel(ax, text):
    ax.axis("off")
    ax.text(0.5, 0.5, text, ha="center", va="center", wrap=True, transform=ax.transAxes)


def draw(out_png, bed_i, bed_ii=None, render_script=None):
    """Fig. 1 into out_png (and .pdf); <out>.txt names the panels not drawn. Returns them."""
    out_png = Path(out_png)
    panels = [("(a) system I", bed_i), ("(c) system II", bed_ii)]
    missing = []
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    with tempfile.TemporaryDirectory() as tmp:
        for ax, (label, bed) in zip((axes[0], axes[2]), panels):
            ax.set_title(label)
            if bed is None:
                why = "the study has no such bed"
            else:
                png = Path(tmp) / f"{label[1]}.png"
                why = render_3d(bed, png, render_script) if render_script else "no renderer given"
            if why:
                missing.append(f"Panel {label.split()[0]} is missing: {why}.")
                note_panel(ax, f"not drawn: {why}")
            else:
                ax.imshow(plt.imread(png))
                ax.axis("off")
    axes[1].set_title("(b) system I, slice through the intruder")
    slice_panel(axes[1], bed_i)
    fig.tight_layout()
    fig.savefig(out_png, dpi=120)
    fig.savefig(out_png.with_suffix(".pdf"))
    plt.close(fig)
    out_png.with_suffix(".txt").write_text(" ".join(missing) + "\n")
    return missing
