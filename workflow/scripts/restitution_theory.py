"""Rule restitution_theory: the Kuwabara-Kono / Brilliantov e(v_n) curve of Fig. 2."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821  (set by Snakemake)
from _setup import start  # noqa: E402

log = start(snakemake)  # noqa: F821
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from analysis.restitution import kuwabara_kono  # noqa: E402
from analysis.table import write_csv  # noqa: E402

sm = snakemake  # noqa: F821
kn, gn, par = float(sm.params.kn), float(sm.params.gamman), sm.params
v = np.geomspace(par.v_min, par.v_max, 200)
write_csv(pd.DataFrame({"v_n": v, "e": kuwabara_kono(v, kn, gn), "kn": kn, "gamman": gn}),
          sm.output[0])
log.info(f"restitution theory: K_n = {kn:g}, gamma_n = {gn:g}, gamma_n/K_n^0.6 = {gn / kn ** 0.6:.5g}")
