# A movie of one pull, an optional target (`snakemake ... movie`, not part of `all`): Fig. 4's
# pull (report.trace) pulled again with `movie.frames` frames over its travel (granudrag pull
# --dump_interval; the run file and its temporal sidecar open in ParaView), rendered headless
# by ParaView and assembled by ffmpeg into report/movie.mp4.

MOVIE_PULL = study.trace_pull(PLAN)


rule movie_pull:
    input:
        granudrag=ancient(GRANUDRAG),
        bed=bed_file(study.poured_bed(MOVIE_PULL.bed, config).key),
    output:
        run=f"{RESULTS}/movie/run.h5",
        sidecar=f"{RESULTS}/movie/run.h5.xdmf",
    log:
        f"{LOGS}/movie/pull.log",
    conda:
        "../envs/granudrag.yaml"
    threads: THREADS
    params:
        args=shlex.join(study.movie_pull_args(MOVIE_PULL, config)),
    shell:
        """
        rm -f {output.run:q}.lock
        {input.granudrag:q} pull --bed {input.bed:q} --output {output.run:q} --threads {threads} --resume {params.args} >{log:q} 2>&1
        """


rule movie:
    input:
        sidecar=rules.movie_pull.output.sidecar,
    output:
        f"{REPORT}/movie.mp4",
    log:
        f"{LOGS}/movie/render.log",
    # ParaView and ffmpeg come from Debian (tools/install-deps.sh); without them the script
    # says which is missing.
    conda:
        "../envs/analysis.yaml"
    params:
        fps=config["movie"]["fps"],
    script:
        "../scripts/movie.py"
