# The simulations: build the engine if it is missing, pour beds, pull intruders.
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
        "(cmake -S {params.source} -B {params.build} -DCMAKE_BUILD_TYPE=Release"
        " && cmake --build {params.build} -j {threads} --target granudrag) > {log} 2>&1"


# A pour checkpoints only when its settling may outlast `checkpoint_minutes` of
# estimated wall time (or a quarter of max_runtime); a rerun after a killed job
# resumes from the checkpoint, unless the arguments changed, and ends with the
# bed an uninterrupted pour gives. With max_runtime, a pour longer than that
# runs over several jobs (retries: enough for the longest).
rule bed:
    input:
        granudrag=ancient(GRANUDRAG),
    output:
        f"{RESULTS}/beds/{{bed}}/bed.h5",
    log:
        f"{LOGS}/beds/{{bed}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/beds/{{bed}}.tsv"
    retries: BED_RETRIES
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    resources:
        mem_mb=bed_mem_mb,
        runtime=bed_runtime,
    params:
        args=pour_args,
    shell:
        """
        ckpt={output}.checkpoint.h5
        args="{params.args}"
        if [ -e "$ckpt" ] && [ "$(cat "$ckpt.args" 2>/dev/null)" != "$args" ]; then
            rm -f "$ckpt"
        fi
        echo "$args" >"$ckpt.args"
        rm -f {output}.lock
        {input.granudrag} pour --output {output} --threads {threads} --resume $args >{log} 2>&1
        rm -f "$ckpt.args"
        """


# A pull checkpoints every tenth of its travel, or every `checkpoint_minutes` of
# estimated wall time if sooner; when a job is killed (a cluster time limit, a
# crash), the rerun resumes from the checkpoint, unless the bed is newer than
# the checkpoint or the arguments changed. With max_runtime, a pull longer than
# that runs over several jobs (retries: enough for the longest).
# Snakemake runs one job per output, so an output lock left beside it is a dead
# job's (possibly on another node, where granudrag cannot tell): the rule removes it.
rule pull:
    input:
        granudrag=ancient(GRANUDRAG),
        bed=f"{RESULTS}/beds/{{bed}}/bed.h5",
    output:
        f"{RESULTS}/pulls/{{bed}}/{{speed}}/run.h5",
    log:
        f"{LOGS}/pulls/{{bed}}/{{speed}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/pulls/{{bed}}/{{speed}}.tsv"
    retries: PULL_RETRIES
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    resources:
        mem_mb=pull_mem_mb,
        runtime=pull_runtime,
    params:
        args=pull_args,
    shell:
        """
        ckpt={output}.checkpoint.h5
        args="{params.args}"
        if [ -e "$ckpt" ] && {{ ! [ "$ckpt" -nt {input.bed} ] || [ "$(cat "$ckpt.args" 2>/dev/null)" != "$args" ]; }}; then
            rm -f "$ckpt"
        fi
        echo "$args" >"$ckpt.args"
        rm -f {output}.lock
        {input.granudrag} pull --bed {input.bed} --output {output} --threads {threads} --resume $args >{log} 2>&1
        rm -f "$ckpt.args"
        """


rule beds:
    input:
        ALL_BEDS,


rule pulls:
    input:
        ALL_RUNS,
