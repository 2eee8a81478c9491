"""A movie of one pull: every frame of its temporal sidecar (granudrag pull --dump_interval)
rendered by ParaView (render_bed.py --frames under pvbatch, headless) and assembled by ffmpeg
into an H.264 MP4, written under a temporary name and renamed when complete.

Usage: python3 movie.py RUN.h5.xdmf OUT.mp4 [FPS]   (or as the movie rule's script)
"""

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from analysis.figures.headless import run_pvbatch

RENDER = Path(__file__).resolve().parent / "render_bed.py"


def missing_tools():
    return [tool for tool in ("pvbatch", "ffmpeg") if shutil.which(tool) is None]


def make_movie(sidecar, out, fps=24):
    missing = missing_tools()
    if missing:
        sys.exit(f"the movie needs {' and '.join(missing)}, not installed: tools/install-deps.sh study "
                 "installs ParaView (pvbatch), Xvfb and ffmpeg from Debian")
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out.parent, prefix=f".{out.name}.") as work:
        run = run_pvbatch(RENDER, "--frames", sidecar, work)
        frames = sorted(Path(work).glob("frame_*.png"))
        if run.returncode != 0 or not frames:
            sys.exit(f"pvbatch could not render {sidecar}:\n{run.stdout}{run.stderr}")
        tmp = Path(work) / "movie.mp4"
        # yuv420p (and even sizes) for players that read nothing else.
        subprocess.run(["ffmpeg", "-y", "-loglevel", "error", "-framerate", str(fps), "-i",
                        str(Path(work) / "frame_%05d.png"), "-c:v", "libx264", "-pix_fmt", "yuv420p",
                        "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", str(tmp)], check=True)
        tmp.replace(out)
    print(f"movie: {out} ({len(frames)} frames at {fps} per second)")


if "snakemake" in globals():
    sm = globals()["snakemake"]
    make_movie(sm.input.sidecar, sm.output[0], sm.params.fps)
elif __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    make_movie(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) == 4 else 24)
