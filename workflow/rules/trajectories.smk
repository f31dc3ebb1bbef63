# Straight paths of Paty 2021 section 3.3.1 (Fig. 10-11).


rule trajectory_table:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        table=f"{RES}/trajectories/{{robot}}_{{pulley}}.csv",
    params:
        design=lambda w: pulley_args(PULLEYS[w.pulley]),
        path=lambda w: PATHS[w.robot],
        n=STUDY["trajectories"]["points"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/trajectory_{{robot}}_{{pulley}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} trajectory --threads {threads} --robot {input.robot} {params.design} --start {params.path[start_m]} --end {params.path[end_m]}"
        " --n {params.n} --out {output.table} > {log} 2>&1"


rule trajectory_figure:
    input:
        tables=expand(f"{RES}/trajectories/{{robot}}_{{pulley}}.csv", robot=PATHS, pulley=PULLEYS),
    output:
        figure=report(f"{RES}/trajectories/trajectories.png", caption="../report/trajectories.rst", category="Trajectories"),
        pdf=f"{RES}/trajectories/trajectories.pdf",
        table=f"{RES}/trajectories/trajectories_minmax.csv",
        minmax=report(f"{RES}/trajectories/trajectories_minmax.png", caption="../report/trajectories_minmax.rst", category="Trajectories"),
        minmax_pdf=f"{RES}/trajectories/trajectories_minmax.pdf",
    params:
        study=uses("trajectories", "pulleys"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/trajectory_figure.log",
    shell:
        "{params.cdpr} job trajectories --study {params.study_file} --tables {input.tables} --table {output.table} --figure {output.figure}"
        " --minmax-figure {output.minmax} > {log} 2>&1"
