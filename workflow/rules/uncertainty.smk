# Uncertainty and sensitivity of the optimal designs (beyond Paty 2021 section 5; cdpr.analyses.uncertainty):
# per-cable Monte Carlo by full solves (shards of samples, seeded per sample) and linearised
# (exact sensitivities), Sobol indices (SALib), dominant-parameter maps; uncompensated and
# compensated. Only for a study with an `uncertainty:` section.
UQ = STUDY.get("uncertainty")
UQ_CASES = ["uncompensated", "compensated"]


if UQ:
    UQ_DESIGNS = list(UQ["designs"])
    UQ_SHARDS = range(UQ["monte_carlo"]["shards"])

    rule uq_shard:
        input:
            box=rules.regular_workspace.output.json,
            robot=DOE_ROBOT,
        output:
            table=f"{RES}/shards/uncertainty/mc_{{design}}_{{case}}_{{shard}}.parquet",
            points=f"{RES}/shards/uncertainty/points_{{design}}_{{case}}_{{shard}}.parquet",
        wildcard_constraints:
            design="|".join(UQ_DESIGNS),
            case="|".join(UQ_CASES),
            shard=r"\d+",
        params:
            study=uses("optimal", "doe", "dead_length_m"),
            uq=uq_uses("seed", "redundancy", "parameters", "monte_carlo", "compensation"),
            cdpr=CDPR,
            study_file=STUDY_FILE,
            code=CODE,
        log:
            f"{RES}/logs/uq_shard_{{design}}_{{case}}_{{shard}}.log",
        threads: SOLVER_THREADS
        shell:
            "{params.cdpr} job uq-shard --threads {threads} --study {params.study_file} --design {wildcards.design} --case {wildcards.case}"
            " --shard {wildcards.shard} --box-file {input.box} --table {output.table} --points {output.points} > {log} 2>&1"

    rule uq_design:
        input:
            box=rules.regular_workspace.output.json,
            robot=DOE_ROBOT,
        output:
            table=f"{RES}/uncertainty/{{design}}_{{case}}_linear.csv",
            path=f"{RES}/uncertainty/{{design}}_{{case}}_path.csv",
            sobol=f"{RES}/uncertainty/{{design}}_{{case}}_sobol.csv",
            tolerances=f"{RES}/uncertainty/{{design}}_{{case}}_tolerances.csv",
            map=f"{RES}/uncertainty/{{design}}_{{case}}_map.csv",
        wildcard_constraints:
            design="|".join(UQ_DESIGNS),
            case="|".join(UQ_CASES),
        params:
            study=uses("optimal", "doe", "dead_length_m", "elasticity", "plane"),
            uq=UQ,
            cdpr=CDPR,
            study_file=STUDY_FILE,
            code=CODE,
        log:
            f"{RES}/logs/uq_design_{{design}}_{{case}}.log",
        threads: SOLVER_THREADS
        shell:
            "{params.cdpr} job uq-design --threads {threads} --study {params.study_file} --design {wildcards.design} --case {wildcards.case}"
            " --box-file {input.box} --table {output.table} --path {output.path} --sobol {output.sobol}"
            " --tolerances {output.tolerances} --map {output.map} > {log} 2>&1"

    rule uncertainty:
        input:
            tables=[
                f"{RES}/shards/uncertainty/{kind}_{d}_{c}_{s}.parquet"
                for kind in ("mc", "points")
                for d in UQ_DESIGNS
                for c in UQ_CASES
                for s in UQ_SHARDS
            ]
            + [
                f"{RES}/uncertainty/{d}_{c}_{what}.csv"
                for d in UQ_DESIGNS
                for c in UQ_CASES
                for what in ("linear", "path", "sobol", "tolerances", "map")
            ],
            paths=[f"{RES}/elasticity/index_vs_E.csv", f"{RES}/elasticity/bands.csv"]
            + [f"{RES}/elasticity/path_{d}_E{e}.csv" for d in UQ_DESIGNS for e in E_PATH],
            paper_values="cdpr/data/paper_values.yaml",
        output:
            bands=f"{RES}/uncertainty/bands.csv",
            agreement=f"{RES}/uncertainty/agreement.csv",
            sobol=f"{RES}/uncertainty/sobol.csv",
            figure=report(f"{RES}/uncertainty/index.png", caption="../report/uq_index.rst", category="Uncertainty"),
            pdf=f"{RES}/uncertainty/index.pdf",
            paths_figure=report(f"{RES}/uncertainty/path.png", caption="../report/uq_path.rst", category="Uncertainty"),
            paths_pdf=f"{RES}/uncertainty/path.pdf",
            sobol_figure=report(f"{RES}/uncertainty/sobol.png", caption="../report/uq_sobol.rst", category="Uncertainty"),
            sobol_pdf=f"{RES}/uncertainty/sobol.pdf",
            map_figure=report(f"{RES}/uncertainty/dominant.png", caption="../report/uq_dominant.rst", category="Uncertainty"),
            map_pdf=f"{RES}/uncertainty/dominant.pdf",
            agreement_figure=report(f"{RES}/uncertainty/agreement.png", caption="../report/uq_agreement.rst", category="Uncertainty"),
            agreement_pdf=f"{RES}/uncertainty/agreement.pdf",
        params:
            study=uses("uncertainty", "paper_comparison", "plane", "doe"),
            cdpr=CDPR,
            study_file=STUDY_FILE,
            code=CODE,
        log:
            f"{RES}/logs/uncertainty.log",
        shell:
            "{params.cdpr} job uncertainty --study {params.study_file} --tables {input.tables} --paths {input.paths}"
            " --bands {output.bands} --agreement {output.agreement} --sobol {output.sobol} --figure {output.figure}"
            " --paths-figure {output.paths_figure} --sobol-figure {output.sobol_figure} --map-figure {output.map_figure}"
            " --agreement-figure {output.agreement_figure} > {log} 2>&1"
