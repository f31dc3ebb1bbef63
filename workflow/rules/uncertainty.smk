# Uncertainty and sensitivity of the optimal designs (beyond Paty 2021 section 5; cdpr.analyses.uncertainty):
# per-cable Monte Carlo by full solves (shards of samples, seeded per sample) and linearised
# (exact sensitivities), Sobol indices (SALib), dominant-parameter maps; uncompensated and
# compensated. Only for a study with an `uncertainty:` section.
from cdpr.pipeline.results import UQ_CASES

UQ = STUDY.get("uncertainty")


if UQ:
    UQ_DESIGNS = LAYOUT.uq_designs()

    rule uq_shard:
        input:
            box=rules.regular_workspace.output.json,
            robot=DOE_ROBOT,
        output:
            **outputs("uq_shard"),
        wildcard_constraints:
            design="|".join(UQ_DESIGNS),
            case="|".join(UQ_CASES),
            shard=r"\d+",
        params:
            **COMMON,
            study=uses("optimal", "doe", "dead_length_m", "wrench"),
            uq=uq_uses("seed", "redundancy", "parameters", "monte_carlo", "compensation"),
        log:
            LAYOUT.log("uq_shard"),
        threads: SOLVER_THREADS
        shell:
            "{params.cdpr} job uq-shard --threads {threads} --study {params.study_file:q} --design {wildcards.design}"
            " --case {wildcards.case} --shard {wildcards.shard} --box-file {input.box:q} --table {output.table:q}"
            " --points {output.points:q}" + TO_LOG

    rule uq_design:
        input:
            box=rules.regular_workspace.output.json,
            robot=DOE_ROBOT,
        output:
            **outputs("uq_design"),
        wildcard_constraints:
            design="|".join(UQ_DESIGNS),
            case="|".join(UQ_CASES),
        params:
            **COMMON,
            study=uses("optimal", "doe", "dead_length_m", "elasticity", "plane", "wrench"),
            uq=UQ,
        log:
            LAYOUT.log("uq_design"),
        threads: SOLVER_THREADS
        shell:
            "{params.cdpr} job uq-design --threads {threads} --study {params.study_file:q} --design {wildcards.design}"
            " --case {wildcards.case} --box-file {input.box:q} --table {output.table:q} --path {output.path:q}"
            " --sobol {output.sobol:q} --tolerances {output.tolerances:q} --map {output.map:q}" + TO_LOG

    rule uncertainty:
        input:
            tables=LAYOUT.paths("uq_shard", "table")
            + LAYOUT.paths("uq_shard", "points")
            + [
                LAYOUT.path("uq_design", what, **c)
                for c in LAYOUT.wildcards("uq_design")
                for what in ("table", "path", "sobol", "tolerances", "map")
            ],
            paths=[LAYOUT.path("elasticity", "table"), LAYOUT.path("elasticity", "bands")]
            + [p for d in UQ_DESIGNS for p in LAYOUT.paths("elasticity_path", "table", design=d)],
            paper_values=PAPER_VALUES,
        output:
            **outputs(
                "uncertainty",
                figure=("../report/uq_index.rst", "Uncertainty"),
                paths_figure=("../report/uq_path.rst", "Uncertainty"),
                sobol_figure=("../report/uq_sobol.rst", "Uncertainty"),
                map_figure=("../report/uq_dominant.rst", "Uncertainty"),
                agreement_figure=("../report/uq_agreement.rst", "Uncertainty"),
                residual_figure=("../report/uq_residual.rst", "Uncertainty"),
            ),
        params:
            **COMMON,
            study=uses("uncertainty", "paper_comparison", "plane", "doe"),
        log:
            LAYOUT.log("uncertainty"),
        shell:
            "{params.cdpr} job uncertainty --study {params.study_file:q} --tables {input.tables:q} --paths {input.paths:q}"
            " --bands {output.bands:q} --agreement {output.agreement:q} --sobol {output.sobol:q} --figure {output.figure:q}"
            " --paths-figure {output.paths_figure:q} --sobol-figure {output.sobol_figure:q} --map-figure {output.map_figure:q}"
            " --agreement-figure {output.agreement_figure:q} --residual-figure {output.residual_figure:q}" + TO_LOG
