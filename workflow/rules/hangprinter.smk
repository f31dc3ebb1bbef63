# Hangprinter study (issue 40; cdpr.pipeline.hangprinter, `cdpr calibrate study`): the published
# sessions of a real Hangprinter (data/hangprinter/) calibrated with the models of
# config/studies/hangprinter.yaml, every model scored by K-fold cross-validation on identical folds
# beside the Hangprinter tool's own solution, and RepRapFirmware's lines of the best model.
# Independent of the paper study; `make reproduce` runs it after the calibration studies. About
# 20 s of CPU on one core (single-threaded BLAS: multi-threaded, the small dense SVDs of the fits
# took ten times longer on the shared 2-core machine).
# Every output path and the results folder come from cdpr.pipeline.results (CALIBRATION_OUTPUTS).
from cdpr.pipeline.hangprinter import load_hangprinter_study

HANGPRINTER_STUDY = "config/studies/hangprinter.yaml"
try:
    HANGPRINTER = load_hangprinter_study(HANGPRINTER_STUDY, check_files=False)
except CdprError as exc:
    raise WorkflowError(f"invalid Hangprinter study: {exc}")
# every file the study reads: per data set its robot, the samples, the tool's solution, the JSON
HANGPRINTER_INPUTS = sorted(
    {
        f
        for d in HANGPRINTER["data_sets"].values()
        for f in (d["robot"], d["data"], d["tool"], d["source"])
        if f is not None
    }
)


def _hangprinter_outputs():
    out = calibration_outputs("hangprinter_study")
    captions = {
        "errors_figure": "hangprinter_errors.rst",
        "anchors_figure": "hangprinter_anchors.rst",
        "force_figure": "hangprinter_force.rst",
    }
    for name, caption in captions.items():
        out[name] = report(out[name], caption=f"../report/{caption}", category="Hangprinter")
    return out


rule hangprinter_study:
    input:
        study=HANGPRINTER_STUDY,
        files=HANGPRINTER_INPUTS,
    output:
        **_hangprinter_outputs(),
    params:
        **common(HANGPRINTER_STUDY),
        out=CALIBRATION_FOLDERS["hangprinter_study"],
    log:
        calibration_log("hangprinter_study"),
    threads: 1
    shell:
        "NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 {params.cdpr} calibrate study --study {params.study_file:q}"
        " --out {params.out:q}" + TO_LOG
