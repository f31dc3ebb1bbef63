rule winch_table:
    output:
        f"{RES}/winch/winch.csv",
    params:
        w=STUDY["winch"],
    log:
        f"{RES}/logs/winch.log",
    shell:
        "{CDPR} winch --lpm-from {params.w[lpm_from_m]} --lpm-to {params.w[lpm_to_m]} --steps {params.w[steps]} --out {output} > {log} 2>&1"


rule winch_figure:
    input:
        rules.winch_table.output,
    output:
        report(f"{RES}/winch/winch.png", caption="../report/winch.rst", category="Winch"),
        f"{RES}/winch/winch.pdf",
        report(f"{RES}/winch/winch_dl.png", caption="../report/winch.rst", category="Winch"),
    shell:
        "{CDPR} plot winch --table {input} --out {output[0]}"
