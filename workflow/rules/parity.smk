# results/<study>/parity.png: every paper number of summary.csv against ours with its tolerance band.


rule parity:
    input:
        table=f"{RES}/summary.csv",
    output:
        figure=report(f"{RES}/parity.png", caption="../report/parity.rst", category="Summary"),
        pdf=f"{RES}/parity.pdf",
    params:
        cdpr=CDPR,
        study_file=STUDY_FILE,
        code=CODE,
    log:
        f"{RES}/logs/parity.log",
    shell:
        "{params.cdpr} job parity-figure --study {params.study_file} --table {input.table} --figure {output.figure} > {log} 2>&1"


PARITY_TARGETS = [f"{RES}/parity.png"] if STUDY.get("paper_comparison") else []
