# Horizontal plane at z (Paty 2021 section 3.3.2): Fig. 12 (|dp|) and Fig. 9 (chosen subsets; taut sets in physical mode).


rule plane_table:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        table=f"{RES}/plane/{{robot}}_{{pulley}}.csv",
    params:
        design=lambda w: pulley_args(PULLEYS[w.pulley]),
        p=STUDY["plane"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/plane_{{robot}}_{{pulley}}.log",
    threads: SOLVER_THREADS
    shell:
        "{params.cdpr} plane --threads {threads} --robot {input.robot} {params.design} --z {params.p[z_m]} --n {params.p[n]}"
        " --out {output.table} > {log} 2>&1"


rule plane_figure:
    input:
        tables=expand(f"{RES}/plane/{{{{robot}}}}_{{pulley}}.csv", pulley=PULLEYS),
        robot=lambda w: ROBOTS[w.robot],
    output:
        figure=report(f"{RES}/plane/{{robot}}.png", caption="../report/plane.rst", category="Plane"),
        pdf=f"{RES}/plane/{{robot}}.pdf",
        tension=report(f"{RES}/plane/{{robot}}_tension.png", caption="../report/plane.rst", category="Plane"),
        tension_pdf=f"{RES}/plane/{{robot}}_tension.pdf",
    params:
        study=uses("plane", "pulleys"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/plane_figure_{{robot}}.log",
    shell:
        "{params.cdpr} job plane-figure --study {params.study_file} --robot-key {wildcards.robot} --tables {input.tables} --figure {output.figure} > {log} 2>&1"


rule subset_figure:
    input:
        tables=expand(f"{RES}/plane/{{{{robot}}}}_{{pulley}}.csv", pulley=PULLEYS),
        robot=lambda w: ROBOTS[w.robot],
    output:
        figure=report(f"{RES}/plane/{{robot}}_subsets.png", caption="../report/subsets.rst", category="Plane"),
        pdf=f"{RES}/plane/{{robot}}_subsets.pdf",
    params:
        study=uses("plane", "pulleys", "redundancy"),
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/subset_figure_{{robot}}.log",
    shell:
        "{params.cdpr} job subsets-figure --study {params.study_file} --robot-key {wildcards.robot} --tables {input.tables} --figure {output.figure} > {log} 2>&1"
