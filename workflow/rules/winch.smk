# Winch of Métillon et al. 2022 (Fig. 7).


rule winch_table:
    output:
        table=f"{RES}/winch/winch.csv",
    params:
        w=STUDY["winch"],
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/winch_table.log",
    shell:
        "{params.cdpr} winch --lpm-from {params.w[lpm_from_m]} --lpm-to {params.w[lpm_to_m]} --steps {params.w[steps]} --out {output.table} > {log} 2>&1"


rule winch_figure:
    input:
        table=rules.winch_table.output.table,
    output:
        figure=report(f"{RES}/winch/winch.png", caption="../report/winch.rst", category="Winch"),
        pdf=f"{RES}/winch/winch.pdf",
    params:
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/winch_figure.log",
    shell:
        "{params.cdpr} job winch-figure --study {params.study_file} --table {input.table} --figure {output.figure} > {log} 2>&1"
