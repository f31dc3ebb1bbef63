rule trajectory_table:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        f"{RES}/trajectories/{{robot}}_{{pulley}}.csv",
    params:
        design=lambda w: design_args(w.pulley),
        path=lambda w: STUDY["trajectories"]["paths"][w.robot],
        n=STUDY["trajectories"]["points"],
    log:
        f"{RES}/logs/trajectory_{{robot}}_{{pulley}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} trajectory --threads {threads} --robot {input.robot} {params.design} --start {params.path[start_m]} --end {params.path[end_m]}"
        " --n {params.n} --out {output} > {log} 2>&1"


rule trajectory_figure:
    input:
        expand(f"{RES}/trajectories/{{robot}}_{{pulley}}.csv", robot=STUDY["trajectories"]["paths"], pulley=PULLEYS),
    output:
        report(f"{RES}/trajectories/trajectories.png", caption="../report/trajectories.rst", category="Trajectories"),
        f"{RES}/trajectories/trajectories.pdf",
        f"{RES}/trajectories/trajectories_minmax.csv",
        report(f"{RES}/trajectories/trajectories_minmax.png", caption="../report/trajectories_minmax.rst", category="Trajectories"),
    params:
        labels=expand("{robot}_{pulley}", robot=STUDY["trajectories"]["paths"], pulley=PULLEYS),
    shell:
        "{CDPR} plot trajectories --table {input} --labels {params.labels} --title '|dp| along the section 3.3.1 paths (Fig. 10)' --out {output[0]}"
