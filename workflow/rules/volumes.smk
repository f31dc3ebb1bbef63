# Error-limited volumes V_L and R_V (Paty 2021 section 3.3.3, Fig. 13-14): solver shards over the frame grid.


rule volume_shard:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        **outputs("volume_shard"),
    params:
        **COMMON,
        study=uses("volumes.n", "volumes.shards", "pulleys", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("volume_shard"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job volume-shard --threads {threads} --study {params.study_file:q} --robot-key {wildcards.robot}"
        " --pulley {wildcards.pulley} --shard {wildcards.shard} --table {output.table:q}" + TO_LOG


rule volumes:
    input:
        tables=LAYOUT.paths("volume_shard", "table"),
        robots=list(ROBOTS.values()),
        paper_values=PAPER_VALUES,
    output:
        **outputs("volumes", figure=("../report/volumes.rst", "Volumes")),
    params:
        **COMMON,
        study=uses("volumes", "pulleys", "dead_length_m", "paper_comparison"),
    log:
        LAYOUT.log("volumes"),
    shell:
        "{params.cdpr} job volumes --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --figure {output.figure:q}" + TO_LOG


rule volume_view:
    input:
        tables=lambda w: LAYOUT.volume_shards(w.label),
        robots=list(ROBOTS.values()),
    output:
        **outputs("volume_view", figure=("../report/volume_view.rst", "Volumes")),
    params:
        **COMMON,
        study=uses("volumes", "pulleys", "dead_length_m"),
    log:
        LAYOUT.log("volume_view"),
    shell:
        "{params.cdpr} job volume-view --study {params.study_file:q} --label {wildcards.label} --tables {input.tables:q}"
        " --figure {output.figure:q}" + TO_LOG


# Error-limited volumes on the orientation error δφ (beyond the paper; a spatial study with
# volumes.dphi_limits_rad): the same frame grids, V_L and R_V of δφ <= limit.
rule volumes_dphi:
    input:
        tables=LAYOUT.paths("volume_shard", "table"),
        robots=list(ROBOTS.values()),
    output:
        **outputs("volumes_dphi", figure=("../report/volumes_dphi.rst", "Volumes")),
    params:
        **COMMON,
        study=uses("volumes", "pulleys", "dead_length_m", "redundancy"),
    log:
        LAYOUT.log("volumes_dphi"),
    shell:
        "{params.cdpr} job volumes-dphi --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --figure {output.figure:q}" + TO_LOG
