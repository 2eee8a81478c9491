# The report: assembled from fits.json and the figure files (no fitting, no drawing), so a
# change to one figure re-runs that figure's rule and this one only.


rule report:
    input:
        table=f"{RESULTS}/table.csv",
        problems=f"{RESULTS}/table_problems.txt",
        fits=f"{REPORT}/fits.json",
        figures=[f"{REPORT}/{name}.png" for name in figure_names.NAMES],
        fig1=f"{REPORT}/fig01_beds.png",
    output:
        html=report(
            f"{REPORT}/report.html",
            caption="../report/report.rst",
            category="Fits and report",
        ),
        md=f"{REPORT}/report.md",
    log:
        f"{LOGS}/report.log",
    conda:
        "../envs/analysis.yaml"
    params:
        n_boot=config["report"]["n_boot"],
        seed=config["report"]["seed"],
    script:
        "../scripts/report.py"
