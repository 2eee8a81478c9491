# From run files to the report: tidy table and P(Z), Fig. 2, 4 and 9 data, fits, figures.


rule table:
    input:
        ALL_RUNS,
    output:
        table=f"{RESULTS}/table.csv",
        problems=f"{RESULTS}/table_problems.txt",
        coordination=f"{RESULTS}/coordination.csv",
    log:
        f"{LOGS}/table.log",
    params:
        repo=str(REPO),
        root=lambda wildcards, output: Path(output.table).parent,
        allow_failed=config["table"]["allow_failed"],
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/make_table.py"


rule restitution:
    input:
        granudrag=ancient(GRANUDRAG),
    output:
        f"{RESULTS}/restitution/engine.csv",
    log:
        f"{LOGS}/restitution.log",
    params:
        speeds=",".join(study.fmt(v) for v in RESTITUTION_SPEEDS),
        kn=REFERENCE_LAW[0],
        gamman=REFERENCE_LAW[1],
    conda:
        "../envs/granudrag.yaml"
    shell:
        "{input.granudrag} restitution --output {output} --speeds {params.speeds}"
        " --kn {params.kn} --gamman {params.gamman} --threads 1 > {log} 2>&1"


rule restitution_theory:
    output:
        f"{RESULTS}/restitution/theory.csv",
    log:
        f"{LOGS}/restitution_theory.log",
    params:
        repo=str(REPO),
        kn=REFERENCE_LAW[0],
        gamman=REFERENCE_LAW[1],
        v_min=config["restitution"]["v_min"],
        v_max=config["restitution"]["v_max"],
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/restitution_theory.py"


rule force_trace:
    input:
        TRACE_RUN,
    output:
        f"{RESULTS}/trace.csv",
    log:
        f"{LOGS}/force_trace.log",
    params:
        repo=str(REPO),
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/force_trace.py"


rule flow_field:
    input:
        [run_file(p.key) for p in study.flow_pulls(PLAN)],
    output:
        f"{RESULTS}/flow_field.csv",
    log:
        f"{LOGS}/flow_field.log",
    params:
        repo=str(REPO),
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/flow_field.py"


rule report:
    input:
        table=f"{RESULTS}/table.csv",
        restitution=f"{RESULTS}/restitution/engine.csv",
        theory=f"{RESULTS}/restitution/theory.csv",
        trace=f"{RESULTS}/trace.csv",
        coordination=f"{RESULTS}/coordination.csv",
        flow=f"{RESULTS}/flow_field.csv",
    output:
        report(
            directory(f"{RESULTS}/report"),
            patterns=["{name}.png"],
            caption="../report/figures.rst",
            category="Figures",
        ),
    log:
        f"{LOGS}/report.log",
    params:
        repo=str(REPO),
        n_boot=config["report"]["n_boot"],
        seed=config["report"]["seed"],
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/make_report.py"
