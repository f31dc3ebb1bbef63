# Paper rule versus physics (one study run in both redundancy modes) and the error budget joining
# both papers (cdpr.pipeline.comparison, cdpr.analyses.budget). The comparison file (config key `comparison`,
# config/comparisons/*.yaml) names the two study files and their results folders; both studies
# must have been run first (`make reproduce` runs paper, physical, then `reproduce_comparison`).
from cdpr.pipeline.comparison import load_comparison
from cdpr.pipeline.tasks import budget_designs

CMP_FILE = config.get("comparison")
if CMP_FILE:
    try:
        CMP = load_comparison(CMP_FILE)
    except CdprError as exc:
        raise WorkflowError(f"invalid comparison configuration: {exc}")
    CMP_DIR = CMP["folder"]
    CMP_STUDY = CMP["paper"]["study"]  # the designs; the physical study differs only in name and redundancy
    CMP_RES = {m: CMP[m]["results"] for m in ("paper", "physical")}
    CMP_DESIGNS = budget_designs(CMP.paper_study)

    # aggregation and the page run beside Snakemake on a cluster (workflow/rules/cluster.smk)
    localrules:
        budget,
        comparison,

    rule budget_design:
        input:
            box=f"{CMP_RES['paper']}/doe/rw_c.json",
            robots=list(CMP.paper_study["robots"].values()),
        output:
            table=f"{CMP_DIR}/budget/{{label}}.csv",
            path=f"{CMP_DIR}/budget/path_{{label}}.csv",
        wildcard_constraints:
            label="|".join(CMP_DESIGNS),
        params:
            budget=CMP["budget"],
            study={k: CMP.paper_study.get(k) for k in ("robots", "pulleys", "optimal", "trajectories", "dead_length_m")},
            cdpr=CDPR,
            study_file=CMP_STUDY,
            comparison_file=CMP_FILE,
            code=CODE,
        log:
            f"{CMP_DIR}/logs/budget_{{label}}.log",
        threads: SOLVER_THREADS
        shell:
            "{params.cdpr} job budget-design --threads {threads} --study {params.study_file} --comparison {params.comparison_file}"
            " --label {wildcards.label} --box-file {input.box} --table {output.table} --path-table {output.path} > {log} 2>&1"

    rule budget:
        input:
            tables=expand(f"{CMP_DIR}/budget/{{label}}.csv", label=CMP_DESIGNS),
            paths=expand(f"{CMP_DIR}/budget/path_{{label}}.csv", label=CMP_DESIGNS),
        output:
            table=f"{CMP_DIR}/budget.csv",
            figure=report(f"{CMP_DIR}/budget.png", caption="../report/budget.rst", category="Comparison"),
            pdf=f"{CMP_DIR}/budget.pdf",
            paths_figure=report(f"{CMP_DIR}/budget_paths.png", caption="../report/budget.rst", category="Comparison"),
            paths_pdf=f"{CMP_DIR}/budget_paths.pdf",
        params:
            study={k: CMP.paper_study.get(k) for k in ("robots", "pulleys", "optimal")},
            cdpr=CDPR,
            study_file=CMP_STUDY,
            comparison_file=CMP_FILE,
            code=CODE,
        log:
            f"{CMP_DIR}/logs/budget.log",
        shell:
            "{params.cdpr} job budget --study {params.study_file} --comparison {params.comparison_file} --tables {input.tables}"
            " --paths {input.paths} --table {output.table} --figure {output.figure} --paths-figure {output.paths_figure} > {log} 2>&1"

    rule comparison:
        input:
            budget=rules.budget.output.table,
            summaries=[f"{CMP_RES[m]}/summary.csv" for m in CMP_RES],
            planes=[
                f"{CMP_RES[m]}/plane/{rk}_{pk}.csv"
                for m in CMP_RES
                for rk in CMP.paper_study["robots"]
                for pk in CMP.paper_study["pulleys"]
            ],
            tables=[
                f"{CMP_RES[m]}/{t}"
                for m in CMP_RES
                for t in (
                    "volumes/volumes.csv",
                    "doe/doe.csv",
                    "doe/effects.csv",
                    "maps/lines.csv",
                    "elasticity/bands.csv",
                    "elasticity/crossings.csv",
                    "elasticity/index_vs_E.csv",
                )
            ]
            + [f"{CMP_RES[m]}/trajectories/CDPR4_{pk}.csv" for m in CMP_RES for pk in CMP.paper_study["pulleys"]]
            + ([f"{CMP_RES[m]}/uncertainty/bands.csv" for m in CMP_RES] if CMP.paper_study.get("uncertainty") else []),
            paper_values="cdpr/data/paper_values.yaml",
        output:
            markdown=CMP["page"],
            table=f"{CMP_DIR}/conclusions.csv",
            figure=report(f"{CMP_DIR}/difference.png", caption="../report/comparison.rst", category="Comparison"),
            pdf=f"{CMP_DIR}/difference.pdf",
            stats=f"{CMP_DIR}/difference_stats.csv",
            overlays=report(f"{CMP_DIR}/overlays.png", caption="../report/comparison.rst", category="Comparison"),
            overlays_pdf=f"{CMP_DIR}/overlays.pdf",
        params:
            study={k: CMP.paper_study.get(k) for k in ("robots", "pulleys", "optimal", "plane", "volumes", "elasticity")},
            cdpr=CDPR,
            study_file=CMP_STUDY,
            comparison_file=CMP_FILE,
            code=CODE,
        log:
            f"{CMP_DIR}/logs/comparison.log",
        shell:
            "{params.cdpr} job comparison --study {params.study_file} --comparison {params.comparison_file} --tables {input.budget}"
            " --table {output.table} --figure {output.figure} --markdown {output.markdown} > {log} 2>&1"

    rule reproduce_comparison:
        input:
            rules.comparison.output.markdown,
