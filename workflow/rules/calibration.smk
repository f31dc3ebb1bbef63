# Calibration study (issue 18; cdpr.pipeline.calibration): a seeded true CDPR4, synthetic tracker
# data, calibrations with the standard / pulley / pulley + elasticity / + winch models (the true robot
# has a drum on every cable), validation over RW_C,
# learning curves, encoder cases. Independent of the paper study; `make reproduce` runs it
# (reproduce-extra hook). About 15-30 s on the 2-core machine.
CALIBRATION_STUDY = "config/studies/calibration.yaml"
CALIBRATION_RES = "results/calibration"


rule calibration_study:
    input:
        study=CALIBRATION_STUDY,
        robot="config/robots/cdpr4.yaml",
    output:
        headline=f"{CALIBRATION_RES}/headline.csv",
        summary=f"{CALIBRATION_RES}/summary.md",
        curve=f"{CALIBRATION_RES}/learning_curve.csv",
        encoder=f"{CALIBRATION_RES}/encoder.csv",
        parameters=f"{CALIBRATION_RES}/parameters.csv",
        figure=f"{CALIBRATION_RES}/learning_curve.png",
    params:
        cdpr=CDPR,
        code=CODE,
        out=CALIBRATION_RES,
    log:
        f"{CALIBRATION_RES}/logs/calibration_study.log",
    threads: 1
    shell:
        "NUMBA_NUM_THREADS=1 {params.cdpr} calibrate study --study {input.study:q} --out {params.out:q}" + TO_LOG


# The 6-DoF part (CoGiRo): a seeded true CoGiRo, synthetic tracker data (position and orientation),
# the standard / pulley / pulley + elasticity models, validation poses in CoGiRo's workspace
# (cdpr.pipeline.calibration6). About 40-60 s on the 2-core machine (the rigid models' stiff solves).
CALIBRATION6_STUDY = "config/studies/calibration_cogiro.yaml"
CALIBRATION6_RES = f"{CALIBRATION_RES}/cogiro"


rule calibration_cogiro:
    input:
        study=CALIBRATION6_STUDY,
        robot="config/robots/cogiro.yaml",
    output:
        headline=f"{CALIBRATION6_RES}/headline.csv",
        summary=f"{CALIBRATION6_RES}/summary.md",
        validation=f"{CALIBRATION6_RES}/validation.csv",
        parameters=f"{CALIBRATION6_RES}/parameters.csv",
        figure=f"{CALIBRATION6_RES}/validation_errors.png",
    params:
        cdpr=CDPR,
        code=CODE,
        out=CALIBRATION6_RES,
    log:
        f"{CALIBRATION6_RES}/logs/calibration_cogiro.log",
    threads: 1
    shell:
        "NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 {params.cdpr} calibrate study --study {input.study:q}"
        " --out {params.out:q}" + TO_LOG
