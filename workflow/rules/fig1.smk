# Fig. 1: 3D views of a system I and a system II bed (ParaView's pvbatch, headless) and the
# slice through the intruder's plane (matplotlib). Without ParaView (the conda environment has
# none: Debian's comes from tools/install-deps.sh) the 3D panels are notes and fig01_beds.txt
# names them; the report adds that to the caption instead of failing.

# The first bed of each system in the plan; the slice is of system I's (else system II's).
FIG1_BEDS = {
    name: bed_file(next(k for k, b in PLAN.beds.items() if b.system == system))
    for name, system in (("bed_i", "I"), ("bed_ii", "II"))
    if any(b.system == system for b in PLAN.beds.values())
}
if "bed_i" not in FIG1_BEDS and FIG1_BEDS:
    FIG1_BEDS = {"bed_i": FIG1_BEDS["bed_ii"]}


rule figure_beds:
    input:
        **FIG1_BEDS,
    output:
        png=f"{REPORT}/fig01_beds.png",
        pdf=f"{REPORT}/fig01_beds.pdf",
        note=f"{REPORT}/fig01_beds.txt",
    log:
        f"{LOGS}/figures/beds.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/fig1.py"
