# Fig. 1: 3D views of a system I and a system II bed (ParaView's pvbatch, headless) and the
# slice through the intruder's plane (matplotlib). Without ParaView the 3D panels are notes and
# fig01_beds.txt names them; the report adds that to the caption instead of failing.


def _fig1_beds():
    beds = {}
    for key, bed in PLAN.beds.items():
        name = {"I": "bed_i", "II": "bed_ii"}.get(bed.system)
        if name and name not in beds:
            beds[name] = bed_file(key)
    if "bed_i" not in beds and beds:
        beds["bed_i"] = beds.pop("bed_ii")
    return beds


rule figure_beds:
    input:
        unpack(lambda wildcards: _fig1_beds()),
    output:
        png=f"{REPORT}/fig01_beds.png",
        pdf=f"{REPORT}/fig01_beds.pdf",
        note=f"{REPORT}/fig01_beds.txt",
    log:
        f"{LOGS}/figures/beds.log",
    script:
        "../scripts/fig1.py"
