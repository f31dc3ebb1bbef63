# Straight paths of Paty 2021 section 3.3.1 (Fig. 10-11).


rule trajectory_table:
    input:
        robot=lambda w: ROBOTS[path_robot(STUDY, w.path)],
    output:
        **outputs("trajectory_table"),
    params:
        **COMMON,
        design=lambda w: pulley_args(PULLEYS[w.pulley]),
        path=lambda w: PATHS[w.path],
        n=STUDY["trajectories"]["points"],
    log:
        LAYOUT.log("trajectory_table"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} trajectory --threads {threads} --robot {input.robot:q} {params.design} --start {params.path[start_m]}"
        " --end {params.path[end_m]} --n {params.n} --out {output.table:q}" + TO_LOG


rule trajectory_figure:
    input:
        tables=LAYOUT.paths("trajectory_table", "table"),
    output:
        **outputs(
            "trajectory_figure",
            figure=("../report/trajectories.rst", "Trajectories"),
            minmax=("../report/trajectories_minmax.rst", "Trajectories"),
        ),
    params:
        **COMMON,
        study=uses("trajectories", "pulleys"),
    log:
        LAYOUT.log("trajectory_figure"),
    shell:
        "{params.cdpr} job trajectories --study {params.study_file:q} --tables {input.tables:q} --table {output.table:q}"
        " --figure {output.figure:q} --minmax-figure {output.minmax:q}" + TO_LOG
