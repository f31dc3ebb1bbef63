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
