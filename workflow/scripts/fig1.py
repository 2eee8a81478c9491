"""Fig. 1 (analysis.figures.figures_bed): the 3D views of a system I and a system II bed rendered by
ParaView (render_bed.py, beside this script, under pvbatch) and the slice through the
intruder's plane.

Usage: python3 fig1.py OUT.png BED_I.h5 [BED_II.h5]   (or as the fig1 rule's script)
"""

import sys
from pathlib import Path

from analysis.figures.figures_bed import draw

RENDER = Path(__file__).resolve().parent / "render_bed.py"

if "snakemake" in globals():
    sm = globals()["snakemake"]
    draw(sm.output.png, sm.input.bed_i, sm.input.get("bed_ii"), RENDER)
elif __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    print("\n".join(draw(*sys.argv[1:], render_script=RENDER)) or "all panels drawn")
