# Error-limited volumes V_L and R_V (section 3.3.3, Fig. 13-14): solver shards over the frame grid.
VOL = STUDY["volumes"]
VOL_LABELS = expand("{robot}_{pulley}", robot=ROBOTS, pulley=PULLEYS)


rule volume_shard:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        f"{RES}/shards/volume/{{robot}}_{{pulley}}_{{shard}}.parquet",
    params:
        design=lambda w: design_args(w.pulley),
    log:
        f"{RES}/logs/volume_{{robot}}_{{pulley}}_{{shard}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} grid --threads {threads} --robot {input.robot} {params.design} --frame --n {VOL[n]} --shard {wildcards.shard} --shards {VOL[shards]}"
        " --out {output} > {log} 2>&1"


def volume_shards(label):
    return expand(f"{RES}/shards/volume/{label}_{{shard}}.parquet", shard=range(VOL["shards"]))


rule volumes:
    input:
        [f for label in VOL_LABELS for f in volume_shards(label)],
    output:
        f"{RES}/volumes/volumes.csv",
        report(f"{RES}/volumes/R_V.png", caption="../report/volumes.rst", category="Volumes"),
    params:
        labels=VOL_LABELS,
    shell:
        "{CDPR} job volumes --study {STUDY_FILE} --labels {params.labels} --shards {VOL[shards]} --inputs {input} --outputs {output}"


rule volume_view:
    input:
        lambda w: volume_shards(w.label),
    output:
        report(f"{RES}/volumes/{{label}}_VL.png", caption="../report/volume_view.rst", category="Volumes"),
    shell:
        "{CDPR} job volume-view --study {STUDY_FILE} --labels {wildcards.label} --inputs {input} --outputs {output}"
