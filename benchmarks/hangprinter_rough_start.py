"""The Hangprinter's held-out target from a rough start (issue 40, "Target, held out"), on the
sessions we have: does ``cdpr calibrate cv --estimate anchors,spools --prior anchors=150mm`` started
from anchors known to +-100 mm predict the held-out measured positions as well as the community
tool (its published solution, and its model re-fitted per fold from the same rough start)?

For each HP4 session with measured positions (config/studies/hangprinter.yaml's data sets with
positions: hp4_2022_force_series2, hp4_2021_12_grid), S rough starts are drawn (seeded): every anchor
coordinate of the reference, the *tool's published anchors* of that session
(data/hangprinter/tool_*.yaml: the best anchors known), is moved by a uniform draw in +-100 mm. Each
rough start is written as RepRapFirmware's M669 line beside the machine's M666 line
(config/robots/hangprinter_hp4.g) and turned into a robot file by ``cdpr import rrf`` itself. Then, on
the study's folds (row i in fold i mod K, each fold count of the study):

- ``cdpr``: ``cdpr calibrate cv --robot rough.yaml --data D --estimate anchors,spools
  --prior anchors=150mm --folds K --model standard`` (the CLI in-process; spools: the documented
  default priors), the study's ``rigid_spools`` model, and the same with ``--model exact`` (the CLI's
  default model, line stretch from the forces; the same numbers on a session without forces);
- ``tool re-fit``: the study's ``tool_model`` (the tool's model re-implemented: rigid lines,
  anchors, spool radii with a 10 mm prior, the one buildup factor held), re-fitted per fold from the
  same rough robot (``cdpr.pipeline.hangprinter.cross_validate_model``);
- ``tool published``: the tool's solution scored as given (``--fixed``; in-sample: it was fitted to
  every sample, held-out ones included).

Per session and fold count it reports the held-out position RMS and median of every start, their
mean and worst over the starts, the ratio cdpr / better of (tool published, tool re-fit) with the
issue's criterion (mean ratio <= 1, worst start <= 1.2: stated met / not met) and, the key finding,
the sensitivity to the start: the anchors fitted on all samples from each start (``cdpr calibrate
fit``'s ``fit_motor``) and their largest distance from the mean over the starts [mm], beside the
starts' own spread. The study's own start (config/robots/hangprinter_hp4.yaml) is row ``study``.

    .venv/bin/python benchmarks/hangprinter_rough_start.py [--starts 10] [--seed 40]
        [--out benchmarks/hangprinter_rough_start]

Writes <out>.csv (one row per session, fold count, start and method), <out>_spread.csv (the fitted
anchors' spread), <out>_buildup.csv (from the study's start, the buildup factor fitted per session
against held at the robot file's value) and <out>.md (the tables quoted by docs/hangprinter.md; tests/pipeline/test_hangprinter_rough_start.py checks the
quote). Deterministic: the same arguments give the same bytes. BLAS single-threaded as the study.
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import io as _io  # noqa: E402
import json  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from cdpr import io  # noqa: E402
from cdpr.analyses import calibration as cal  # noqa: E402
from cdpr.analyses.calibration.motor import BUILDUP_PRIOR_SD  # noqa: E402
from cdpr.cli.main import main as cdpr_main  # noqa: E402
from cdpr.pipeline import hangprinter as hp  # noqa: E402
from cdpr.robot import load_robot  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "config" / "studies" / "hangprinter.yaml"
#: The machine's RepRapFirmware configuration: its M666 line (spools) is kept, M669 is the rough start.
CONFIG_G = ROOT / "config" / "robots" / "hangprinter_hp4.g"
#: The issue's tape measurement: each anchor coordinate known to +-100 mm.
HALF_WIDTH_MM = 100.0
#: The issue's prior for a tape measurement; the spools' priors are the documented defaults.
PRIOR = "anchors=150mm"
GROUPS = ["anchors", "spools"]
#: The issue's criterion: on average no worse, on no session worse than 1.2x.
WORST_RATIO = 1.2
FORMAT = "%.6g"


def cli(argv):
    """Run ``cdpr`` in-process; its stdout (stderr discarded: import notes), exits on failure."""
    out, err = _io.StringIO(), _io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cdpr_main(argv)
    if code:
        raise SystemExit(f"cdpr {' '.join(argv)} failed ({code}): {err.getvalue().strip()}")
    return out.getvalue()


def rough_robot(anchors_m, folder, name):
    """The robot file ``cdpr import rrf`` writes from M669 with ``anchors_m`` (m, 3) [m] and the
    machine's M666 line."""
    m666 = next(ln for ln in CONFIG_G.read_text().splitlines() if ln.startswith("M666"))
    a = np.round(1e3 * np.asarray(anchors_m), 2)
    m669 = "M669 K6 " + " ".join(f"{'ABCD'[i]}{x:.2f}:{y:.2f}:{z:.2f}" for i, (x, y, z) in enumerate(a))
    g = Path(folder) / f"{name}.g"
    g.write_text(f"; rough start {name}\n{m669}\n{m666}\n")
    out = Path(folder) / f"{name}.yaml"
    cli(["import", "rrf", "--config", str(g), "--out", str(out), "--name", name])
    return out


def cv_cli(robot, data, K, model):
    """Held-out position RMS, median [mm] of ``cdpr calibrate cv`` from ``robot``."""
    res = json.loads(
        cli(
            [
                "calibrate", "cv", "--robot", str(robot), "--data", str(data), "--estimate",
                "anchors,spools", "--prior", PRIOR, "--folds", str(K), "--model", model, "--json",
            ]
        )
    )  # fmt: skip
    return 1e3 * res["heldout_position_rms_m"], 1e3 * res["heldout_position_median_m"]


def run(starts, seed, folder):
    """The rows of the CSV (module docstring) and the fitted anchors per session and start."""
    st = hp.load_hangprinter_study(STUDY)
    rows, anchors = [], {}
    for si, (ds, spec) in enumerate(st["data_sets"].items()):
        study_robot = load_robot(spec["robot"])
        data = cal.read_motor_data(spec["data"], study_robot)
        if not data.has_pose.any() or spec["tool"] is None:
            continue  # no measured position (HP3): nothing to score
        tool = load_robot(spec["tool"])
        ref = cal.SpoolModel.of(tool).A
        rng = np.random.default_rng([seed, si])
        draws = {"study": Path(spec["robot"])}
        for s in range(starts):
            A = ref + rng.uniform(-HALF_WIDTH_MM, HALF_WIDTH_MM, ref.shape) / 1e3
            draws[f"start_{s + 1}"] = rough_robot(A, folder, f"{ds}_start_{s + 1}")
        for k in st["folds"]:
            K = hp._fold_count(k, len(data.sample))
            pub = cal.cross_validate(tool, data, folds=K, model="standard", fixed=True)
            for start, path in draws.items():
                robot = load_robot(path)
                start_dev = 1e3 * np.abs(cal.SpoolModel.of(robot).A - ref).max()
                res = hp.cross_validate_model(st, "tool_model", robot, data, K)
                out = {
                    "cdpr_standard": cv_cli(path, spec["data"], K, "standard"),
                    "cdpr_exact": cv_cli(path, spec["data"], K, "exact"),
                    "tool_refit": (
                        1e3 * res["heldout_position_rms_m"],
                        1e3 * res["heldout_position_median_m"],
                    ),
                    "tool_published": (
                        1e3 * pub["heldout_position_rms_m"],
                        1e3 * pub["heldout_position_median_m"],
                    ),
                }
                for method, (rms, med) in out.items():
                    rows.append(
                        {
                            "data_set": ds,
                            "folds": K,
                            "leave_one_out": k == "leave-one-out",
                            "start": start,
                            "start_max_deviation_mm": start_dev,
                            "method": method,
                            "heldout_position_rms_mm": rms,
                            "heldout_position_median_mm": med,
                        }
                    )
        for start, path in draws.items():
            robot = load_robot(path)
            for model in ("standard", "exact"):
                fit = cal.fit_motor(robot, data, GROUPS, cal.parse_motor_priors(PRIOR, GROUPS), model)
                anchors[(ds, start, model)] = fit.spool_model.A
    return pd.DataFrame(rows), anchors


def spread_rows(anchors):
    """Per session and model: the largest distance [mm] of an anchor fitted from a rough start from
    the mean over the rough starts, and from the fit from the study's start."""
    out = []
    for ds, model in dict.fromkeys((k[0], k[2]) for k in anchors):
        rough = np.array([A for (d, s, m), A in anchors.items() if d == ds and m == model and s != "study"])
        study = anchors[(ds, "study", model)]
        mean = rough.mean(axis=0)
        out.append(
            {
                "data_set": ds,
                "model": model,
                "fit_spread_mm": 1e3 * np.linalg.norm(rough - mean, axis=2).max(),
                "fit_from_study_start_mm": 1e3 * np.linalg.norm(rough - study, axis=2).max(),
            }
        )
    return pd.DataFrame(out)


def buildup_rows():
    """Per session and fold count, from the study's start: ``--model standard --estimate
    anchors,spools`` with the buildup factor fitted per cable for the session (the documented default
    prior sd, ``BUILDUP_PRIOR_SD``) against held at the robot file's value (prior sd 1 nm)."""
    st = hp.load_hangprinter_study(STUDY)
    out = []
    for ds, spec in st["data_sets"].items():
        robot = load_robot(spec["robot"])
        data = cal.read_motor_data(spec["data"], robot)
        if not data.has_pose.any():
            continue
        for k in st["folds"]:
            K = hp._fold_count(k, len(data.sample))
            for label, sd in (("fitted per session", BUILDUP_PRIOR_SD), ("held", 1e-9)):
                priors = {**cal.parse_motor_priors(PRIOR, GROUPS), "buildup": sd}
                res = cal.cross_validate(robot, data, GROUPS, priors, model="standard", folds=K)
                out.append(
                    {
                        "data_set": ds,
                        "folds": K,
                        "buildup": label,
                        "buildup_prior_sd_mm": 1e3 * sd,
                        "heldout_position_rms_mm": 1e3 * res["heldout_position_rms_m"],
                        "heldout_position_median_mm": 1e3 * res["heldout_position_median_m"],
                        "heldout_line_rms_mm": 1e3 * res["heldout_line_rms_m"],
                    }
                )
    return pd.DataFrame(out)


def buildup_table(b):
    """The markdown table of <out>_buildup.csv.

    Parameters
    ----------
    b : DataFrame

    Returns
    -------
    str
    """
    head = ["session", "K", "buildup factor", "held-out position RMS", "median", "held-out line RMS"]
    lines = [io.md_row(head), "|" + "---|" * len(head)]
    for r in b.itertuples():
        cells = [r.data_set, str(r.folds), r.buildup, _f(r.heldout_position_rms_mm)]
        lines.append(io.md_row(cells + [_f(r.heldout_position_median_mm), _f(r.heldout_line_rms_mm)]))
    return "\n".join(lines) + "\n"


def _f(x):
    return f"{x:.3g}"


def summary_table(df, spread):
    """The markdown table of the CSVs: per session, fold count and method the held-out position
    RMS (mean over the rough starts, the worst start, the study's start), the median's mean, the
    ratio to the better reference and the criterion; the anchors' spread over the starts.

    Parameters
    ----------
    df : DataFrame
        <out>.csv.
    spread : DataFrame
        <out>_spread.csv.

    Returns
    -------
    str
    """
    head = [
        "session", "K", "method", "RMS: mean over starts", "worst start", "study's start",
        "median: mean", "mean / tool re-fit", "mean / better tool", "worst / better tool", "criterion",
    ]  # fmt: skip
    lines = [io.md_row(head), "|" + "---|" * len(head)]
    for (ds, K), d in df.groupby(["data_set", "folds"], sort=False):
        rough = d[d.start != "study"]
        stats = {}
        for method, m in rough.groupby("method", sort=False):
            stats[method] = (m.heldout_position_rms_mm.mean(), m.heldout_position_rms_mm.max())
        pub = rough[rough.method == "tool_published"].set_index("start").heldout_position_rms_mm
        refit = rough[rough.method == "tool_refit"].set_index("start").heldout_position_rms_mm
        better = np.minimum(pub, refit)  # per start: the better of the two references
        for method, m in rough.groupby("method", sort=False):
            rms = m.set_index("start").heldout_position_rms_mm
            study = d[(d.start == "study") & (d.method == method)].heldout_position_rms_mm.iloc[0]
            cells = [ds, str(K), method, _f(stats[method][0]), _f(stats[method][1]), _f(study)]
            cells.append(_f(m.heldout_position_median_mm.mean()))
            if method.startswith("cdpr"):
                mean_ratio = rms.mean() / better.mean()
                worst_ratio = (rms / better).max()
                met = mean_ratio <= 1.0 and worst_ratio <= WORST_RATIO
                cells += [f"{rms.mean() / refit.mean():.2f}", f"{mean_ratio:.2f}", f"{worst_ratio:.2f}"]
                cells.append("met" if met else "**not met**")
            else:
                cells += ["", "", "", ""]
            lines.append(io.md_row(cells))
    lines += [
        "",
        io.md_row(["session", "model", "fitted anchors: spread over starts", "from the study's start"]),
    ]
    lines.append("|" + "---|" * 4)
    for r in spread.itertuples():
        lines.append(io.md_row([r.data_set, r.model, _f(r.fit_spread_mm), _f(r.fit_from_study_start_mm)]))
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--starts", type=int, default=10, help="rough starts per session")
    p.add_argument("--seed", type=int, default=40)
    p.add_argument("--out", default=str(ROOT / "benchmarks" / "hangprinter_rough_start"))
    a = p.parse_args()
    t0, c0 = time.time(), time.process_time()
    with tempfile.TemporaryDirectory() as tmp:
        df, anchors = run(a.starts, a.seed, tmp)
    spread = spread_rows(anchors)
    buildup = buildup_rows()
    out = Path(a.out)
    io.atomic(
        out.with_suffix(".csv"),
        lambda tmp: df.to_csv(tmp, index=False, float_format=FORMAT, lineterminator="\n"),
    )
    io.atomic(
        out.with_name(out.name + "_spread.csv"),
        lambda tmp: spread.to_csv(tmp, index=False, float_format=FORMAT, lineterminator="\n"),
    )
    io.atomic(
        out.with_name(out.name + "_buildup.csv"),
        lambda tmp: buildup.to_csv(tmp, index=False, float_format=FORMAT, lineterminator="\n"),
    )
    text = summary_table(df, spread) + "\n" + buildup_table(buildup)
    io.write_text(text, out.with_suffix(".md"))
    print(text)
    print(f"{a.starts} starts: wall {time.time() - t0:.0f} s, CPU {time.process_time() - c0:.0f} s")


if __name__ == "__main__":
    main()
