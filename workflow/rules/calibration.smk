# Calibration study (issue 18; cdpr.pipeline.calibration): a seeded true CDPR4, synthetic tracker
# data, calibrations with the standard / pulley / pulley + elasticity / + winch models (the true robot
# has a drum on every cable), validation over RW_C,
# learning curves, encoder cases. Independent of the paper study; `make reproduce` runs it
# (reproduce-extra hook). About 15-30 s on the 2-core machine.
# Every output path and the results folders come from cdpr.pipeline.results (CALIBRATION_OUTPUTS).
from cdpr.pipeline.results import CALIBRATION_FOLDERS, calibration_log, calibration_outputs

CALIBRATION_STUDY = "config/studies/calibration.yaml"


rule calibration_study:
    input:
        study=CALIBRATION_STUDY,
        robot="config/robots/cdpr4.yaml",
    output:
        **calibration_outputs("calibration_study"),
    params:
        **common(CALIBRATION_STUDY),
        out=CALIBRATION_FOLDERS["calibration_study"],
    log:
        calibration_log("calibration_study"),
    threads: 1
    shell:
        "NUMBA_NUM_THREADS=1 {params.cdpr} calibrate study --study {params.study_file:q} --out {params.out:q}" + TO_LOG


# The 6-DoF part (CoGiRo): a seeded true CoGiRo, synthetic tracker data (position and orientation),
# the standard / pulley / pulley + elasticity models, validation poses in CoGiRo's workspace
# (cdpr.pipeline.calibration, the rigid platform's study). About 40-60 s on the 2-core machine (the
# rigid models' stiff solves).
CALIBRATION_COGIRO_STUDY = "config/studies/calibration_cogiro.yaml"


rule calibration_cogiro:
    input:
        study=CALIBRATION_COGIRO_STUDY,
        robot="config/robots/cogiro.yaml",
    output:
        **calibration_outputs("calibration_cogiro"),
    params:
        **common(CALIBRATION_COGIRO_STUDY),
        out=CALIBRATION_FOLDERS["calibration_cogiro"],
    log:
        calibration_log("calibration_cogiro"),
    threads: 1
    shell:
        "NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 {params.cdpr} calibrate study --study {params.study_file:q}"
        " --out {params.out:q}" + TO_LOG
