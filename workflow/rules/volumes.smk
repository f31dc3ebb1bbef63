# Error-limited volumes V_L and R_V (Paty 2021 section 3.3.3, Fig. 13-14): solver shards over the frame grid.
VOL = STUDY["volumes"]
VOL_LABELS = expand("{robot}_{pulley}", robot=ROBOTS, pulley=PULLEYS)


rule volume_shard:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        table=f"{RES}/shards/volume/{{robot}}_{{pulley}}_{{shard}}.parquet",
    params:
        design=lambda w: pulley_args(PULLEYS[w.pulley]),
        n=VOL["n"],
        shards=VOL["shards"],
        code=CODE,
    log:
        f"{RES}/logs/volume_{{robot}}_{{pulley}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} grid --threads {threads} --robot {input.robot} {params.design} --frame --n {params.n} --shard {wildcards.shard}"
        " --shards {params.shards} --out {output.table} > {log} 2>&1"


def volume_shards(label):
    return expand(f"{RES}/shards/volume/{label}_{{shard}}.parquet", shard=range(VOL["shards"]))


rule volumes:
    input:
        tables=[f for label in VOL_LABELS for f in volume_shards(label)],
        robots=list(ROBOTS.values()),
    output:
        table=f"{RES}/volumes/volumes.csv",
        figure=report(f"{RES}/volumes/R_V.png", caption="../report/volumes.rst", category="Volumes"),
        pdf=f"{RES}/volumes/R_V.pdf",
    params:
        study=uses("volumes", "pulleys", "dead_length_m", "paper_comparison"),
        code=CODE,
    log:
        f"{RES}/logs/volumes.log",
    shell:
        "{CDPR} job volumes --study {STUDY_FILE} --tables {input.tables} --table {output.table} --figure {output.figure} > {log} 2>&1"


rule volume_view:
    input:
        tables=lambda w: volume_shards(w.label),
        robots=list(ROBOTS.values()),
    output:
        figure=report(f"{RES}/volumes/{{label}}_VL.png", caption="../report/volume_view.rst", category="Volumes"),
        pdf=f"{RES}/volumes/{{label}}_VL.pdf",
    params:
        study=uses("volumes", "pulleys", "dead_length_m"),
        code=CODE,
    log:
        f"{RES}/logs/volume_view_{{label}}.log",
    shell:
        "{CDPR} job volume-view --study {STUDY_FILE} --label {wildcards.label} --tables {input.tables} --figure {output.figure} > {log} 2>&1"
