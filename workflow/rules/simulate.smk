# The simulations: build the engine if it is missing, pour beds, pull intruders.
# One attempt of a pour or a pull: resume, keep a finished run, keep every log.
RESUMABLE = str(REPO / "workflow" / "scripts" / "resumable.sh")
# The engine is an input marked ancient(): rebuilding it does not make every
# result out of date (re-run a result by deleting it, or with --forcerun).


rule build_granudrag:
    output:
        GRANUDRAG,
    log:
        f"{LOGS}/build_granudrag.log",
    conda:
        "../envs/granudrag.yaml"
    # Snakemake lowers it to the cores given (--cores); workflow.cores is not set under
    # Snakemake 9 without --cores (--report, a cluster executor).
    threads: 16
    params:
        source=REPO,
        build=lambda wildcards, output: Path(output[0]).parent,
    shell:
        "(cmake -S {params.source:q} -B {params.build:q} -DCMAKE_BUILD_TYPE=Release"
        " && cmake --build {params.build:q} -j {threads} --target granudrag) > {log:q} 2>&1"


# A pour checkpoints only when its settling may outlast `checkpoint_minutes` of
# estimated wall time (or a quarter of max_runtime); a rerun after a killed job
# resumes from the checkpoint, unless the arguments changed, and ends with the
# bed an uninterrupted pour gives. With max_runtime, a pour longer than that
# runs over several jobs (retries: enough for the longest). A job killed after
# its pour finished keeps the bed for the next attempt (scripts/resumable.sh).
rule bed:
    input:
        granudrag=ancient(GRANUDRAG),
    output:
        study.bed_file(RESULTS, f"{{bed,{POURED_BED}}}"),
    log:
        study.log_file(LOGS, "beds", "{bed}"),
    benchmark:
        study.benchmark_file(RESULTS, "beds", "{bed}")
    retries: BED_RETRIES
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    resources:
        mem_mb=bed_mem_mb,
        runtime=bed_runtime,
        attempt=lambda wildcards, attempt: attempt,
    params:
        args=pour_args,
        resumable=RESUMABLE,
    shell:
        "{params.resumable:q} {output:q} {log:q} {resources.attempt} {params.args:q} ''"
        " -- {input.granudrag:q} pour --output {output:q} --threads {threads} --resume {params.args}"


# A placed system's (`placement:`) column: its bed's pour without an intruder, once per system,
# contact law and seed, checkpointed and resumed as a bed's.
rule column:
    input:
        granudrag=ancient(GRANUDRAG),
    output:
        study.column_file(RESULTS, "{column}"),
    log:
        study.log_file(LOGS, "columns", "{column}"),
    benchmark:
        study.benchmark_file(RESULTS, "columns", "{column}")
    retries: BED_RETRIES
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    resources:
        mem_mb=column_mem_mb,
        runtime=column_runtime,
        attempt=lambda wildcards, attempt: attempt,
    params:
        args=column_args,
        resumable=RESUMABLE,
    shell:
        "{params.resumable:q} {output:q} {log:q} {resources.attempt} {params.args:q} ''"
        " -- {input.granudrag:q} pour --output {output:q} --threads {threads} --resume {params.args}"


# A placed system's bed: its intruder placed into its seed's column (granudrag place), the column
# read only. A placement is short and has no checkpoint: a killed one starts over (granudrag
# writes the bed atomically, so a failed placement leaves none); a new column re-places its beds.
rule placed_bed:
    input:
        granudrag=ancient(GRANUDRAG),
        column=column_of_bed,
    output:
        study.bed_file(RESULTS, f"{{bed,{PLACED_BED}}}"),
    log:
        study.log_file(LOGS, "beds", "{bed}"),
    benchmark:
        study.benchmark_file(RESULTS, "beds", "{bed}")
    retries: BED_RETRIES
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    resources:
        mem_mb=bed_mem_mb,
        runtime=bed_runtime,
        attempt=lambda wildcards, attempt: attempt,
    params:
        args=place_args,
        resumable=RESUMABLE,
    shell:
        "{params.resumable:q} {output:q} {log:q} {resources.attempt} {params.args:q} {input.column:q}"
        " -- {input.granudrag:q} place --bed {input.column:q} --output {output:q} --threads {threads} {params.args}"


# A pull checkpoints every tenth of its travel, or every `checkpoint_minutes` of
# estimated wall time if sooner; when a job is killed (a cluster time limit, a
# crash), the rerun resumes from the checkpoint, unless the bed is newer than
# the checkpoint or the arguments changed. With max_runtime, a pull longer than
# that runs over several jobs (retries: enough for the longest).
# Snakemake runs one job per output, so an output lock left beside it is a dead
# job's (possibly on another node, where granudrag cannot tell): the rule removes it.
# A job killed at its time limit after the pull finished keeps the run for the
# next attempt; every attempt's output stays in the log (scripts/resumable.sh).
rule pull:
    input:
        granudrag=ancient(GRANUDRAG),
        bed=poured_bed_file,
    output:
        study.run_file(RESULTS, "{bed}/{speed}"),
    log:
        study.log_file(LOGS, "pulls", "{bed}/{speed}"),
    benchmark:
        study.benchmark_file(RESULTS, "pulls", "{bed}/{speed}")
    retries: PULL_RETRIES
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    resources:
        mem_mb=pull_mem_mb,
        runtime=pull_runtime,
        attempt=lambda wildcards, attempt: attempt,
    params:
        args=pull_args,
        resumable=RESUMABLE,
    shell:
        "{params.resumable:q} {output:q} {log:q} {resources.attempt} {params.args:q} {input.bed:q}"
        " -- {input.granudrag:q} pull --bed {input.bed:q} --output {output:q} --threads {threads} --resume {params.args}"


rule beds:
    input:
        ALL_BEDS,


rule columns:
    input:
        ALL_COLUMNS,


rule pulls:
    input:
        ALL_RUNS,
