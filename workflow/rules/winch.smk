# Winch of Métillon et al. 2022 (Fig. 7).


rule winch_table:
    output:
        **outputs("winch_table"),
    params:
        **COMMON,
        w=STUDY["winch"],
    log:
        LAYOUT.log("winch_table"),
    shell:
        "{params.cdpr} winch --lpm-from {params.w[lpm_from_m]} --lpm-to {params.w[lpm_to_m]} --steps {params.w[steps]}"
        " --out {output.table:q}" + TO_LOG


rule winch_figure:
    input:
        table=rules.winch_table.output.table,
    output:
        **outputs("winch_figure", figure=("../report/winch.rst", "Winch")),
    params:
        **COMMON,
    log:
        LAYOUT.log("winch_figure"),
    shell:
        "{params.cdpr} job winch-figure --study {params.study_file:q} --table {input.table:q} --figure {output.figure:q}" + TO_LOG
