# Horizontal plane at z (Paty 2021 section 3.3.2): Fig. 12 (|dp|) and Fig. 9 (chosen subsets; taut sets in physical mode).


rule plane_table:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        **outputs("plane_table"),
    params:
        **COMMON,
        study=uses("plane.z_m", "plane.n", "pulleys", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("plane_table"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job plane-table --threads {threads} --study {params.study_file:q} --robot-key {wildcards.robot}"
        " --pulley {wildcards.pulley} --table {output.table:q}" + TO_LOG


rule plane_figure:
    input:
        tables=lambda w: LAYOUT.paths("plane_table", "table", robot=w.robot),
        robot=lambda w: ROBOTS[w.robot],
    output:
        **outputs("plane_figure", figure=("../report/plane.rst", "Plane"), tension=("../report/plane.rst", "Plane")),
    params:
        **COMMON,
        study=uses("plane", "pulleys"),
    log:
        LAYOUT.log("plane_figure"),
    shell:
        "{params.cdpr} job plane-figure --study {params.study_file:q} --robot-key {wildcards.robot} --tables {input.tables:q}"
        " --figure {output.figure:q}" + TO_LOG


rule subset_figure:
    input:
        tables=lambda w: LAYOUT.paths("plane_table", "table", robot=w.robot),
        robot=lambda w: ROBOTS[w.robot],
    output:
        **outputs("subset_figure", figure=("../report/subsets.rst", "Plane")),
    params:
        **COMMON,
        study=uses("plane", "pulleys", "redundancy"),
    log:
        LAYOUT.log("subset_figure"),
    shell:
        "{params.cdpr} job subsets-figure --study {params.study_file:q} --robot-key {wildcards.robot} --tables {input.tables:q}"
        " --figure {output.figure:q}" + TO_LOG
