# Straight paths of Paty 2021 section 3.3.1 (Fig. 10-11).


rule trajectory_table:
    input:
        robot=lambda w: ROBOTS[path_robot(STUDY, w.path)],
    output:
        **outputs("trajectory_table"),
    params:
        **COMMON,
        study=uses("trajectories.paths", "trajectories.points", "pulleys", "dead_length_m", "solver", "redundancy", "rotvec_rad", "wrench"),
    log:
        LAYOUT.log("trajectory_table"),
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} job trajectory-table --threads {threads} --study {params.study_file:q} --path-label {wildcards.path}"
        " --pulley {wildcards.pulley} --table {output.table:q}" + TO_LOG


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
