# The figures, by families that share their data. Each reads the fits from fits.json (no
# refitting) and writes <name>.png and .pdf in the report directory; a figure whose data the
# study lacks is drawn as a note saying why. Captions: workflow/report/<name>.rst.


rule figure_restitution:
    input:
        restitution=f"{RESULTS}/restitution/engine.csv",
        theory=f"{RESULTS}/restitution/theory.csv",
    output:
        figure_files("Contact law", "fig02_restitution"),
    log:
        f"{LOGS}/figures/restitution.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figure_force_trace:
    input:
        trace=f"{RESULTS}/trace.csv",
    output:
        figure_files("Drag", "fig04_force_trace"),
    log:
        f"{LOGS}/figures/force_trace.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figures_drag:
    input:
        table=f"{RESULTS}/table.csv",
        fits=f"{REPORT}/fits.json",
    output:
        figure_files(
            "Drag",
            "fig05_drag_vs_Fr_mu0.5",
            "fig10_drag_vs_Fr_mu0",
            "table1_mu0_regime1",
            "fig11_quasistatic_vs_mu",
            "fig16_drag_vs_Fr_depth",
        ),
    log:
        f"{LOGS}/figures/drag.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figures_contacts:
    input:
        table=f"{RESULTS}/table.csv",
        fits=f"{REPORT}/fits.json",
    output:
        figure_files("Contacts", "fig06_theta_vs_Fr", "fig08_kappa_vs_Fr"),
    log:
        f"{LOGS}/figures/contacts.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figure_coordination:
    input:
        coordination=f"{RESULTS}/coordination.csv",
    output:
        figure_files("Contacts", "fig07_coordination_distribution"),
    log:
        f"{LOGS}/figures/coordination.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figure_flow_field:
    input:
        flow=f"{RESULTS}/flow_field.csv",
    output:
        figure_files("Flow", "fig09_flow_field"),
    log:
        f"{LOGS}/figures/flow_field.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figures_yield:
    input:
        table=f"{RESULTS}/table.csv",
        fits=f"{REPORT}/fits.json",
    output:
        figure_files(
            "Yield force",
            "fig12_yield_vs_mu",
            "fig13_yield_vs_D",
            "fig14_phi_vs_mu",
            "fig17_yield_vs_h",
            "fig18_alpha_and_sum_rule",
        ),
    log:
        f"{LOGS}/figures/yield.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figures_scaling:
    input:
        table=f"{RESULTS}/table.csv",
        fits=f"{REPORT}/fits.json",
    output:
        figure_files(
            "Scaling law", "fig15_scaled_drag_vs_Fr_D", "fig19_scaled_drag_vs_Fr_h"
        ),
    log:
        f"{LOGS}/figures/scaling.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"


rule figure_contact_law:
    input:
        table=f"{RESULTS}/table.csv",
    output:
        figure_files("Contact law", "fig20_kn_gamman"),
    log:
        f"{LOGS}/figures/contact_law.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/figures.py"
