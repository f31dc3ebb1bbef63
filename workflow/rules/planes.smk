rule plane_table:
    input:
        robot=lambda w: ROBOTS[w.robot],
    output:
        f"{RES}/plane/{{robot}}_{{pulley}}.csv",
    params:
        design=lambda w: design_args(w.pulley),
        p=STUDY["plane"],
    log:
        f"{RES}/logs/plane_{{robot}}_{{pulley}}.log",
    threads: SOLVER_THREADS
    shell:
        "{CDPR} plane --threads {threads} --robot {input.robot} {params.design} --z {params.p[z_m]} --n {params.p[n]} --out {output} > {log} 2>&1"


rule plane_figure:
    input:
        rules.plane_table.output,
    output:
        report(f"{RES}/plane/{{robot}}_{{pulley}}.png", caption="../report/plane.rst", category="Plane z = 2.5 m"),
        f"{RES}/plane/{{robot}}_{{pulley}}.pdf",
    shell:
        "{CDPR} plot plane --table {input} --title '{wildcards.robot} {wildcards.pulley}: |dp| [m]' --out {output[0]}"


rule subset_figure:
    input:
        rules.plane_table.output,
    output:
        report(f"{RES}/plane/{{robot}}_{{pulley}}_subsets.png", caption="../report/subsets.rst", category="Plane z = 2.5 m"),
        f"{RES}/plane/{{robot}}_{{pulley}}_subsets.pdf",
    shell:
        "{CDPR} plot subsets --table {input} --title '{wildcards.robot} {wildcards.pulley}: subset minimising |dp|' --out {output[0]}"
