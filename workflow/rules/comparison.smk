# Paper rule versus physics (one study run in both redundancy modes) and the error budget joining
# both papers (cdpr.pipeline.comparison, cdpr.analyses.budget). The comparison file (config key `comparison`,
# config/comparisons/*.yaml) names the two study files and their results folders; both studies
# must have been run first (`make reproduce` runs paper, physical, then `reproduce_comparison`).
# Every path comes from cdpr.pipeline.results.ComparisonLayout.
from cdpr.pipeline.comparison import load_comparison
from cdpr.pipeline.results import ComparisonLayout

CMP_FILE = config.get("comparison")
if CMP_FILE:
    try:
        CMP = load_comparison(CMP_FILE)
    except CdprError as exc:
        raise WorkflowError(f"invalid comparison configuration: {exc}")
    CMP_LAYOUT = ComparisonLayout(CMP)
    CMP_STUDY = CMP["paper"]["study"]  # the designs; the physical study differs only in name and redundancy
    CMP_DESIGNS = CMP_LAYOUT.labels()
    # the params of every comparison rule: the command, the paper study and the comparison file, the code
    CMP_COMMON = common(CMP_STUDY, comparison_file=CMP_FILE)

    def cmp_outputs(rule, **reports):
        """The outputs of a comparison rule (cdpr.pipeline.results), figures in the report."""
        out = CMP_LAYOUT.outputs(rule)
        for name, (caption, category) in reports.items():
            out[name] = report(out[name], caption=caption, category=category)
        return out

    # aggregation and the page run beside Snakemake on a cluster (workflow/rules/cluster.smk)
    localrules:
        budget,
        comparison,

    rule budget_design:
        input:
            box=CMP_LAYOUT.studies["paper"].path("regular_workspace", "json"),
            robots=list(CMP.paper_study["robots"].values()),
        output:
            **cmp_outputs("budget_design"),
        wildcard_constraints:
            label="|".join(CMP_DESIGNS),
        params:
            **CMP_COMMON,
            budget=CMP["budget"],
            study={k: CMP.paper_study.get(k) for k in ("robots", "pulleys", "optimal", "trajectories", "dead_length_m", "wrench")},
        log:
            CMP_LAYOUT.log("budget_design"),
        threads: SOLVER_THREADS
        shell:
            "{params.cdpr} job budget-design --threads {threads} --study {params.study_file:q} --comparison {params.comparison_file:q}"
            " --label {wildcards.label} --box-file {input.box:q} --table {output.table:q} --path-table {output.path:q}" + TO_LOG

    rule budget:
        input:
            tables=CMP_LAYOUT.paths("budget_design", "table"),
            paths=CMP_LAYOUT.paths("budget_design", "path"),
        output:
            **cmp_outputs(
                "budget",
                figure=("../report/budget.rst", "Comparison"),
                paths_figure=("../report/budget.rst", "Comparison"),
            ),
        params:
            **CMP_COMMON,
            study={k: CMP.paper_study.get(k) for k in ("robots", "pulleys", "optimal")},
        log:
            CMP_LAYOUT.log("budget"),
        shell:
            "{params.cdpr} job budget --study {params.study_file:q} --comparison {params.comparison_file:q} --tables {input.tables:q}"
            " --paths {input.paths:q} --table {output.table:q} --figure {output.figure:q} --paths-figure {output.paths_figure:q}"
            + TO_LOG

    rule comparison:
        input:
            budget=rules.budget.output.table,
            tables=CMP_LAYOUT.inputs(),
            paper_values=PAPER_VALUES,
        output:
            **cmp_outputs("comparison", figure=("../report/comparison.rst", "Comparison"), overlays=("../report/comparison.rst", "Comparison"), planes=("../report/comparison_planes.rst", "Comparison")),
        params:
            **CMP_COMMON,
            study={k: CMP.paper_study.get(k) for k in ("robots", "pulleys", "optimal", "plane", "volumes", "elasticity")},
        log:
            CMP_LAYOUT.log("comparison"),
        shell:
            "{params.cdpr} job comparison --study {params.study_file:q} --comparison {params.comparison_file:q} --tables {input.budget:q}"
            " --table {output.table:q} --figure {output.figure:q} --markdown {output.markdown:q}" + TO_LOG

    rule reproduce_comparison:
        input:
            CMP_LAYOUT.targets(),
