# Error-limited volumes V_L and R_V (Paty 2021 section 3.3.3, Fig. 13-14): solver shards over the frame grid.


rule volume_shard:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        table=f"{RES}/shards/volume/{{robot}}_{{pulley}}_{{shard}}.parquet",
    params:
        design=lambda w: pulley_args(PULLEYS[w.pulley]),
        n=VOL["n"],
        shards=VOL["shards"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/volume_{{robot}}_{{pulley}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} grid --threads {threads} --robot {input.robot} {params.design} --frame --n {params.n} --shard {wildcards.shard}"
        " --shards {params.shards} --out {output.table} > {log} 2>&1"


rule volumes:
    input:
        tables=[f for label in VOL_LABELS for f in volume_shards(label)],
        robots=list(ROBOTS.values()),
        paper_values="cdpr/data/paper_values.yaml",
    output:
        table=f"{RES}/volumes/volumes.csv",
        figure=report(f"{RES}/volumes/R_V.png", caption="../report/volumes.rst", category="Volumes"),
        pdf=f"{RES}/volumes/R_V.pdf",
    params:
        study=uses("volumes", "pulleys", "dead_length_m", "paper_comparison"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/volumes.log",
    shell:
        "{params.cdpr} job volumes --study {params.study_file} --tables {input.tables} --table {output.table} --figure {output.figure} > {log} 2>&1"


rule volume_view:
    input:
        tables=lambda w: volume_shards(w.label),
        robots=list(ROBOTS.values()),
    output:
        figure=report(f"{RES}/volumes/{{label}}_VL.png", caption="../report/volume_view.rst", category="Volumes"),
        pdf=f"{RES}/volumes/{{label}}_VL.pdf",
    params:
        study=uses("volumes", "pulleys", "dead_length_m"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/volume_view_{{label}}.log",
    shell:
        "{params.cdpr} job volume-view --study {params.study_file} --label {wildcards.label} --tables {input.tables} --figure {output.figure} > {log} 2>&1"
