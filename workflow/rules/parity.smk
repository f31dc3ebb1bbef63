# results/<study>/parity.png: every paper number of summary.csv against ours with its tolerance band
# (the paper's study only: cdpr.pipeline.results lists it when paper_comparison is true).


rule parity:
    input:
        table=LAYOUT.path("summary", "table"),
    output:
        **outputs("parity", figure=("../report/parity.rst", "Summary")),
    params:
        **COMMON,
    log:
        LAYOUT.log("parity"),
    shell:
        "{params.cdpr} job parity-figure --study {params.study_file:q} --table {input.table:q} --figure {output.figure:q}"
        + TO_LOG
