"""ParaView's pvbatch without a display: under a virtual X server (xvfb-run) when there is one.

`xvfb-run -a` looks for a free display from :99 up, and two started at the same moment can
both take :99 (Fig. 1, the movie and the ParaView tests render side by side in a workflow or a
test run): each command here starts its search at a random display number instead. On a
loaded machine pvbatch has also been seen to lose its fresh X server at random ("bad X server
connection", a few runs in ten under load, never alone): that one failure, which is the
display's and not the render's, is retried on a new display, up to TRIES times, with a pause
that grows each time (3 immediate tries all lost their display once, 2026-11-26, on a machine
running a test suite and a validation study at once).
"""

import random
import shutil
import subprocess
import time

TRIES = 5
PAUSE = 2.0   # s before the second try; doubled before each next one
LOST_DISPLAY = "bad X server connection"


def pvbatch_command(script, *args):
    """The command that runs `pvbatch script args...` headless."""
    if shutil.which("xvfb-run"):
        return ["xvfb-run", "-a", "-n", str(random.randint(100, 30000)), "pvbatch", str(script), *map(str, args)]
    return ["pvbatch", "--force-offscreen-rendering", str(script), *map(str, args)]


def run_pvbatch(script, *args, timeout=3600):
    """Runs pvbatch headless (CompletedProcess, text output captured); a run that lost its X
    display is run again on another."""
    for attempt in range(TRIES):
        if attempt:
            time.sleep(PAUSE * 2 ** (attempt - 1))
        run = subprocess.run(pvbatch_command(script, *args), capture_output=True, text=True, timeout=timeout)
        if run.returncode == 0 or LOST_DISPLAY not in run.stdout + run.stderr:
            return run
    return run
