# From run files to the data of the figures: tidy table and P(Z), the Fig. 2, 4 and 9 data,
# and every fit (fits.json, bootstraps included: the figures and the report only read it).
# With table.allow_failed, a pull the engine stopped leaves a placeholder that the table lists
# (table_problems.txt, failed_pulls.txt) and leaves out; the end of the run removes the
# placeholders and failed_pulls.txt, so that the next run makes the table again and retries them.


rule table:
    input:
        runs=ALL_RUNS,
        plan=PLAN_FILE,
    output:
        table=f"{RESULTS}/table.csv",
        runs=f"{RESULTS}/runs.csv",
        problems=f"{RESULTS}/table_problems.txt",
        failed=f"{RESULTS}/failed_pulls.txt",
        coordination=f"{RESULTS}/coordination.csv",
    log:
        f"{LOGS}/table.log",
    conda:
        "../envs/analysis.yaml"
    params:
        root=lambda wildcards, output: Path(output.table).parent,
        allow_failed=config["table"]["allow_failed"],
        yield_speed=config["report"].get("yield_speed", 0.01),
        bed_scatter=config["table"].get("bed_scatter"),
    script:
        "../scripts/make_table.py"


rule restitution:
    input:
        granudrag=ancient(GRANUDRAG),
    output:
        f"{RESULTS}/restitution/engine.csv",
    log:
        f"{LOGS}/restitution.log",
    conda:
        "../envs/granudrag.yaml"
    params:
        speeds=",".join(study.fmt(v) for v in RESTITUTION_SPEEDS),
        kn=REFERENCE_LAW[0],
        gamman=REFERENCE_LAW[1],
    shell:
        "{input.granudrag:q} restitution --output {output:q} --speeds {params.speeds:q}"
        " --kn {params.kn:q} --gamman {params.gamman:q} --threads 1 > {log:q} 2>&1"


rule restitution_theory:
    output:
        f"{RESULTS}/restitution/theory.csv",
    log:
        f"{LOGS}/restitution_theory.log",
    conda:
        "../envs/analysis.yaml"
    params:
        kn=REFERENCE_LAW[0],
        gamman=REFERENCE_LAW[1],
        v_min=config["restitution"]["v_min"],
        v_max=config["restitution"]["v_max"],
    script:
        "../scripts/restitution_theory.py"


rule force_trace:
    input:
        TRACE_RUN,
    output:
        f"{RESULTS}/trace.csv",
    log:
        f"{LOGS}/force_trace.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/force_trace.py"


rule flow_field:
    input:
        FLOW_RUNS,
    output:
        f"{RESULTS}/flow_field.csv",
    log:
        f"{LOGS}/flow_field.log",
    conda:
        "../envs/analysis.yaml"
    script:
        "../scripts/flow_field.py"


# Every fit of the report, once: the regime fits with their wild bootstrap (report.n_boot
# refits), theta(Fr), kappa(Fr), phi_mu, alpha_mu (from F_Y, and the paper's average over
# report.alpha_speeds), the sum rules, F_Y(mu) saturation, and the lambdas of Eq. 12 (pulls
# at h >= report.h_min). The same as `python -m analysis fit` with those options.
rule fits:
    input:
        f"{RESULTS}/table.csv",
    output:
        report(
            f"{REPORT}/fits.json",
            caption="../report/fits.rst",
            category="Fits and report",
        ),
    log:
        f"{LOGS}/fits.log",
    conda:
        "../envs/analysis.yaml"
    params:
        options=study.fit_options(config).to_dict(),
    script:
        "../scripts/fits.py"


# A validation study's comparison (config/validate/*.yaml set `validation`): its runs
# against the reference protocol, a figure, the table of comparisons and the sentence.
if config.get("validation"):

    rule validation:
        input:
            f"{RESULTS}/runs.csv",
        output:
            multiext(
                f"{RESULTS}/validate_{config['validation']}",
                ".png",
                ".pdf",
                ".csv",
                ".md",
            ),
        log:
            f"{LOGS}/validation.log",
        conda:
            "../envs/analysis.yaml"
        params:
            study=config["validation"],
            outdir=RESULTS,
        script:
            "../scripts/validate.py"
