"""Rule restitution_theory: the Kuwabara-Kono / Brilliantov e(v_n) curve of Fig. 2."""

import numpy as np
import pandas as pd

from analysis.core.physics import gamman_ratio
from analysis.core.restitution import kuwabara_kono
from analysis.core.table import write_csv
from granudrag_study.script import start

log = start(snakemake)
kn, gn, par = float(snakemake.params.kn), float(snakemake.params.gamman), snakemake.params
v = np.geomspace(par.v_min, par.v_max, 200)
write_csv(pd.DataFrame({"v_n": v, "e": kuwabara_kono(v, kn, gn), "kn": kn, "gamman": gn}), snakemake.output[0])
log.info(f"restitution theory: K_n = {kn:g}, gamma_n = {gn:g}, gamma_n/K_n^0.6 = {gamman_ratio(kn, gn):.5g}")
