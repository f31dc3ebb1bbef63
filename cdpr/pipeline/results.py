"""The one description of a results folder: every file a study's pipeline writes, by rule.

A study (``config/studies/*.yaml``) writes its results under one folder (``results/<study>/``); a
comparison (``config/comparisons/*.yaml``) writes its page and a folder of its own. This module is
the only place that spells these paths: the Snakemake rules take their outputs and inputs from it
(``workflow/rules/common.smk``), the target rules request every file it lists (so that a missing
file, an intermediate one included, is rebuilt), and the summary and the comparison read their
tables through it.

``STUDY_OUTPUTS`` maps each rule to its outputs, as patterns relative to the results folder with
Snakemake's ``{wildcard}`` fields; ``Layout(study, folder)`` expands them over the study's robots,
pulley designs, DOE tests, shards, Young's moduli, ... (``Layout.wildcards``). Logs go to
``logs/<rule>...log`` (``STUDY_LOGS``), which are not results and not targets.

The calibration studies (``config/studies/calibration*.yaml``, ``cdpr calibrate study``) have a
folder each (``CALIBRATION_FOLDERS``) and their files in ``CALIBRATION_OUTPUTS`` and
``CALIBRATION_LOGS``: ``cdpr.pipeline.calibration`` writes them by these names
(``rel_path``) and ``workflow/rules/calibration.smk`` declares them (``calibration_outputs``); so does
the Hangprinter study (``hangprinter_study``: ``cdpr.pipeline.hangprinter``,
``workflow/rules/hangprinter.smk``).
"""

from __future__ import annotations

import itertools
from pathlib import Path

from cdpr.analyses.uncertainty import CASES
from cdpr.errors import CdprError
from cdpr.pipeline.study import budget_designs, doe_tests, map_kinds, uq_cases
from cdpr.robot import load_robot

#: rule -> output name -> path under the results folder ({wildcards} filled by ``Layout.wildcards``).
#: Every figure is a PNG with a PDF beside it; both are outputs of their rule.
STUDY_OUTPUTS = {
    "winch_table": {"table": "winch/winch.csv"},
    "winch_figure": {"figure": "winch/winch.png", "pdf": "winch/winch.pdf"},
    "plane_table": {"table": "plane/{robot}_{pulley}.csv"},
    "plane_figure": {
        "figure": "plane/{robot}.png",
        "pdf": "plane/{robot}.pdf",
        "tension": "plane/{robot}_tension.png",
        "tension_pdf": "plane/{robot}_tension.pdf",
    },
    "subset_figure": {"figure": "plane/{robot}_subsets.png", "pdf": "plane/{robot}_subsets.pdf"},
    "trajectory_table": {"table": "trajectories/{path}_{pulley}.csv"},
    "trajectory_figure": {
        "figure": "trajectories/trajectories.png",
        "pdf": "trajectories/trajectories.pdf",
        "table": "trajectories/trajectories_minmax.csv",
        "minmax": "trajectories/trajectories_minmax.png",
        "minmax_pdf": "trajectories/trajectories_minmax.pdf",
    },
    "volume_shard": {"table": "shards/volume/{robot}_{pulley}_{shard}.parquet"},
    "volumes": {"table": "volumes/volumes.csv", "figure": "volumes/R_V.png", "pdf": "volumes/R_V.pdf"},
    "volume_view": {"figure": "volumes/{label}_VL.png", "pdf": "volumes/{label}_VL.pdf"},
    "volumes_dphi": {
        "table": "volumes/volumes_dphi.csv",
        "figure": "volumes/R_V_dphi.png",
        "pdf": "volumes/R_V_dphi.pdf",
    },
    "workspace_grid": {"table": "shards/workspace/test{test}.parquet"},
    "regular_workspace": {"table": "doe/rw_max.csv", "json": "doe/rw_c.json"},
    "robot_view": {"figure": "robot/{robot}.png", "pdf": "robot/{robot}.pdf"},
    "index_shard": {"table": "shards/doe/tests_{shard}.parquet"},
    "doe": {
        "table": "doe/doe.csv",
        "effects": "doe/effects.csv",
        "figure": "doe/responses.png",
        "pdf": "doe/responses.pdf",
        "effects_figure": "doe/effects.png",
        "effects_pdf": "doe/effects.pdf",
    },
    "map_kind": {"table": "shards/maps/{kind}.csv"},
    "maps": {
        "map": "maps/map.csv",
        "lines": "maps/lines.csv",
        "figure": "maps/maps.png",
        "pdf": "maps/maps.pdf",
    },
    "elasticity_shard": {"table": "shards/elasticity/{design}_{shard}.parquet"},
    "elasticity_path": {"table": "elasticity/path_{design}_E{E}.csv"},
    "elasticity": {
        "table": "elasticity/index_vs_E.csv",
        "bands": "elasticity/bands.csv",
        "crossings": "elasticity/crossings.csv",
        "figure": "elasticity/index_vs_E.png",
        "pdf": "elasticity/index_vs_E.pdf",
        "paths_figure": "elasticity/paths.png",
        "paths_pdf": "elasticity/paths.pdf",
    },
    "dead_length_point": {"table": "shards/dead_length/points.csv"},
    "dead_length": {
        "table": "dead_length/dead_length.csv",
        "figure": "dead_length/dead_length.png",
        "pdf": "dead_length/dead_length.pdf",
    },
    "uq_shard": {
        "table": "shards/uncertainty/mc_{design}_{case}_{shard}.parquet",
        "points": "shards/uncertainty/points_{design}_{case}_{shard}.parquet",
    },
    "uq_design": {
        "table": "uncertainty/{design}_{case}_linear.csv",
        "path": "uncertainty/{design}_{case}_path.csv",
        "sobol": "uncertainty/{design}_{case}_sobol.csv",
        "tolerances": "uncertainty/{design}_{case}_tolerances.csv",
        "map": "uncertainty/{design}_{case}_map.csv",
    },
    "uncertainty": {
        "bands": "uncertainty/bands.csv",
        "agreement": "uncertainty/agreement.csv",
        "sobol": "uncertainty/sobol.csv",
        "figure": "uncertainty/index.png",
        "pdf": "uncertainty/index.pdf",
        "paths_figure": "uncertainty/path.png",
        "paths_pdf": "uncertainty/path.pdf",
        "sobol_figure": "uncertainty/sobol.png",
        "sobol_pdf": "uncertainty/sobol.pdf",
        "map_figure": "uncertainty/dominant.png",
        "map_pdf": "uncertainty/dominant.pdf",
        "agreement_figure": "uncertainty/agreement.png",
        "agreement_pdf": "uncertainty/agreement.pdf",
        "residual_figure": "uncertainty/residual.png",
        "residual_pdf": "uncertainty/residual.pdf",
    },
    "study_budget_design": {"table": "budget/{design}.csv"},
    "study_budget": {"table": "budget/budget.csv", "figure": "budget/budget.png", "pdf": "budget/budget.pdf"},
    "sag_path": {"table": "sag/path.csv", "figure": "sag/path.png", "pdf": "sag/path.pdf"},
    "sag_corner": {"table": "sag/corner.csv", "figure": "sag/corner.png", "pdf": "sag/corner.pdf"},
    "summary": {"markdown": "summary.md", "table": "summary.csv"},
    "parity": {"figure": "parity.png", "pdf": "parity.pdf"},
    "conclusions": {"markdown": "conclusions.md", "table": "conclusions.csv"},
}


#: The fit of the best model that both calibration studies write under ``exact/`` (its samples and
#: the three figures of ``calibration_figures``).
_EXACT = {
    "samples": "exact/samples.csv",
    "residuals": "exact/residuals.png",
    "residuals_pdf": "exact/residuals.pdf",
    "estimates": "exact/estimates.png",
    "estimates_pdf": "exact/estimates.pdf",
    "correlation": "exact/correlation.png",
    "correlation_pdf": "exact/correlation.pdf",
}

#: The calibration studies (``cdpr calibrate study``, ``workflow/rules/calibration.smk``): rule ->
#: output name -> path under the study's results folder (``CALIBRATION_FOLDERS``), as
#: ``STUDY_OUTPUTS``. ``calibration_study`` is the CDPR4 study (``cdpr.pipeline.calibration``),
#: ``calibration_cogiro`` the 6-DoF one (the same module); ``exact/`` holds the fit
#: of the best model (its samples and the three figures of ``calibration_figures``).
CALIBRATION_OUTPUTS = {
    "calibration_study": {
        "headline": "headline.csv",
        "summary": "summary.md",
        "curve": "learning_curve.csv",
        "encoder": "encoder.csv",
        "parameters": "parameters.csv",
        "figure": "learning_curve.png",
        "pdf": "learning_curve.pdf",
        **_EXACT,
    },
    "calibration_cogiro": {
        "headline": "headline.csv",
        "summary": "summary.md",
        "validation": "validation.csv",
        "parameters": "parameters.csv",
        "figure": "validation_errors.png",
        "pdf": "validation_errors.pdf",
        **_EXACT,
    },
    # the Hangprinter study (``cdpr.pipeline.hangprinter``): real sessions, cross-validated models
    "hangprinter_study": {
        "cv": "cv.csv",
        "per_sample": "per_sample.csv",
        "parameters": "parameters.csv",
        "fits": "fits.csv",
        "line_lengths": "line_lengths.csv",
        "firmware": "firmware.g",
        "summary": "summary.md",
        "errors_figure": "heldout_errors.png",
        "errors_pdf": "heldout_errors.pdf",
        "anchors_figure": "anchors.png",
        "anchors_pdf": "anchors.pdf",
        "force_figure": "residuals_force.png",
        "force_pdf": "residuals_force.pdf",
    },
}
#: rule -> the results folder the pipeline gives the calibration study (``--out``).
CALIBRATION_FOLDERS = {
    "calibration_study": "results/calibration",
    "calibration_cogiro": "results/calibration/cogiro",
    "hangprinter_study": "results/hangprinter",
}
#: rule -> its log under its results folder.
CALIBRATION_LOGS = {
    "calibration_study": "logs/calibration_study.log",
    "calibration_cogiro": "logs/calibration_cogiro.log",
    "hangprinter_study": "logs/hangprinter_study.log",
}


def rel_path(rule, name="table", **wildcards):
    """Where ``rule`` writes its output ``name`` in a study's results folder (``STUDY_OUTPUTS``, or
    ``CALIBRATION_OUTPUTS`` for a calibration study), a relative path with ``wildcards`` filled in:
    the one spelling of a results file that ``summary``, ``comparison``, the tasks and the
    calibration studies read and write (the rules take ``Layout`` and ``calibration_outputs``)."""
    outputs = CALIBRATION_OUTPUTS if rule in CALIBRATION_OUTPUTS else STUDY_OUTPUTS
    return outputs[rule][name].format(**wildcards)


def calibration_outputs(rule, folder=None):
    """Output name -> path of a calibration rule (``CALIBRATION_OUTPUTS``) under ``folder`` (default
    its ``CALIBRATION_FOLDERS`` entry): the rule's ``output``."""
    folder = CALIBRATION_FOLDERS[rule] if folder is None else folder
    return {name: _join(folder, rel) for name, rel in CALIBRATION_OUTPUTS[rule].items()}


def calibration_log(rule, folder=None):
    """The log of a calibration rule under ``folder`` (default its ``CALIBRATION_FOLDERS`` entry)."""
    return _join(CALIBRATION_FOLDERS[rule] if folder is None else folder, CALIBRATION_LOGS[rule])


#: rule -> its log under the results folder (one per job: the wildcards of its outputs).
STUDY_LOGS = {
    "winch_table": "logs/winch_table.log",
    "winch_figure": "logs/winch_figure.log",
    "plane_table": "logs/plane_{robot}_{pulley}.log",
    "plane_figure": "logs/plane_figure_{robot}.log",
    "subset_figure": "logs/subset_figure_{robot}.log",
    "trajectory_table": "logs/trajectory_{path}_{pulley}.log",
    "trajectory_figure": "logs/trajectory_figure.log",
    "volume_shard": "logs/volume_{robot}_{pulley}_{shard}.log",
    "volumes": "logs/volumes.log",
    "volume_view": "logs/volume_view_{label}.log",
    "volumes_dphi": "logs/volumes_dphi.log",
    "workspace_grid": "logs/workspace_test{test}.log",
    "regular_workspace": "logs/regular_workspace.log",
    "robot_view": "logs/robot_view_{robot}.log",
    "index_shard": "logs/doe_tests_{shard}.log",
    "doe": "logs/doe.log",
    "map_kind": "logs/map_{kind}.log",
    "maps": "logs/maps.log",
    "elasticity_shard": "logs/elasticity_{design}_{shard}.log",
    "elasticity_path": "logs/elasticity_path_{design}_E{E}.log",
    "elasticity": "logs/elasticity.log",
    "dead_length_point": "logs/dead_length_point.log",
    "dead_length": "logs/dead_length.log",
    "uq_shard": "logs/uq_shard_{design}_{case}_{shard}.log",
    "uq_design": "logs/uq_design_{design}_{case}.log",
    "uncertainty": "logs/uncertainty.log",
    "study_budget_design": "logs/budget_{design}.log",
    "study_budget": "logs/budget.log",
    "sag_path": "logs/sag_path.log",
    "sag_corner": "logs/sag_corner.log",
    "summary": "logs/summary.log",
    "parity": "logs/parity.log",
    "conclusions": "logs/conclusions.log",
}

#: The two cases of the uncertainty study (``analyses.uncertainty.CASES``, re-exported for the
#: rules): lengths as commanded, and compensated with the nominal model; a study runs
#: ``study.uq_cases`` of them.
UQ_CASES = CASES

#: rule -> output name -> path of a comparison (``{folder}`` and ``{page}`` from the comparison file).
COMPARISON_OUTPUTS = {
    "budget_design": {"table": "{folder}/budget/{label}.csv", "path": "{folder}/budget/path_{label}.csv"},
    "budget": {
        "table": "{folder}/budget.csv",
        "figure": "{folder}/budget.png",
        "pdf": "{folder}/budget.pdf",
        "paths_figure": "{folder}/budget_paths.png",
        "paths_pdf": "{folder}/budget_paths.pdf",
    },
    "comparison": {
        "markdown": "{page}",
        "table": "{folder}/conclusions.csv",
        "figure": "{folder}/difference.png",
        "pdf": "{folder}/difference.pdf",
        "stats": "{folder}/difference_stats.csv",
        "overlays": "{folder}/overlays.png",
        "overlays_pdf": "{folder}/overlays.pdf",
        "planes": "{folder}/planes.png",
        "planes_pdf": "{folder}/planes.pdf",
    },
}
COMPARISON_LOGS = {
    "budget_design": "{folder}/logs/budget_{label}.log",
    "budget": "{folder}/logs/budget.log",
    "comparison": "{folder}/logs/comparison.log",
}


def _join(folder, rel):
    return f"{str(folder).rstrip('/')}/{rel}"


def _product(**values):
    """Every combination of the given wildcard values, in order (the last varies fastest)."""
    keys = list(values)
    return [dict(zip(keys, combo)) for combo in itertools.product(*values.values())]


class Layout:
    """The results folder of one study: every output path, by rule.

    Parameters
    ----------
    st : cdpr.pipeline.study.Study
        The validated study (``load_study``).
    folder : str or Path
        Its results folder (``results/<study>``); paths are ``folder/<pattern>``.
    """

    def __init__(self, st, folder):
        self.st = st
        self.folder = str(folder).rstrip("/") or "."

    # ---- the study's wildcard values -----------------------------------------------------------
    def robots(self):
        return list(self.st["robots"])

    def redundant_robots(self):
        """Robots with more cables than degrees of freedom: the subset map (Fig. 9) applies to them."""
        models = self.st.robot_models
        if models is None:
            models = {k: load_robot(p) for k, p in self.st["robots"].items()}
        return [k for k, robot in models.items() if robot.m > 3]

    def E_path(self):
        """Young's moduli of the section 5.2 paths, as written in file names."""
        return [f"{float(e):.6g}" for e in self.st["elasticity"]["E_path_Pa"]]

    def tests(self):
        return [int(t) for t in doe_tests(self.st).test]

    def uq_designs(self):
        u = self.st.get("uncertainty")
        return list(u["designs"]) if u else []

    def wildcards(self, rule):
        """The wildcard values the study runs ``rule`` over: a list of dicts (one per job)."""
        st = self.st
        robots, pulleys = self.robots(), list(st["pulleys"])
        designs, u = list(st["optimal"]), st.get("uncertainty")
        one = [{}]
        table = {
            "plane_table": lambda: _product(robot=robots, pulley=pulleys),
            "plane_figure": lambda: _product(robot=robots),
            "subset_figure": lambda: _product(robot=self.redundant_robots()),
            "trajectory_table": lambda: _product(path=list(st["trajectories"]["paths"]), pulley=pulleys),
            "volume_shard": lambda: _product(
                robot=robots, pulley=pulleys, shard=range(st["volumes"]["shards"])
            ),
            "volume_view": lambda: _product(label=[f"{r}_{p}" for r in robots for p in pulleys]),
            "robot_view": lambda: _product(robot=robots),  # every robot: point masses and rigid platforms
            "workspace_grid": lambda: _product(test=self.tests()),
            "index_shard": lambda: _product(shard=range(st["doe"]["shards"])),
            "map_kind": lambda: _product(kind=self.map_kinds()),
            "elasticity_shard": lambda: _product(design=designs, shard=range(st["elasticity"]["shards"])),
            "elasticity_path": lambda: _product(design=designs, E=self.E_path()),
            "uq_shard": lambda: _product(
                design=self.uq_designs(), case=uq_cases(st), shard=range(u["monte_carlo"]["shards"])
            ),
            "uq_design": lambda: _product(design=self.uq_designs(), case=uq_cases(st)),
            "study_budget_design": lambda: _product(design=designs),
        }
        if rule not in STUDY_OUTPUTS:
            raise CdprError(f"unknown rule {rule!r}; the rules of a study: {', '.join(STUDY_OUTPUTS)}")
        if rule in ("uq_shard", "uq_design", "uncertainty") and not u:
            return []
        if rule in ("study_budget_design", "study_budget") and not st.get("budget"):
            return []  # the error budget: a study with a `budget` key (rigid platform, or physical mode)
        if rule == "volumes_dphi" and not st["volumes"].get("dphi_limits_rad"):
            return []  # the volumes on δφ: a spatial study with volumes.dphi_limits_rad
        if rule in ("sag_path", "sag_corner") and not st.get("sag"):
            return []  # what sag adds: a study with a `sag` section (the large study)
        if rule == "parity" and not st.get("paper_comparison"):
            return []  # the parity chart draws the paper's numbers: the paper's study only
        if rule == "conclusions" and not st.get("conclusions"):
            return []  # the paper's conclusions on another robot: a study that names its reference
        return table[rule]() if rule in table else one

    def map_kinds(self):
        return map_kinds(self.st)

    def rules(self):
        """The rules this study runs (the uncertainty rules only with an ``uncertainty`` section)."""
        return [r for r in STUDY_OUTPUTS if self.wildcards(r)]

    # ---- paths -----------------------------------------------------------------------------------
    def outputs(self, rule):
        """Output name -> pattern under the folder, with its ``{wildcards}`` (a rule's ``output``)."""
        return {name: _join(self.folder, rel) for name, rel in STUDY_OUTPUTS[rule].items()}

    def log(self, rule):
        """The pattern of the rule's log under the folder (a rule's ``log``)."""
        return _join(self.folder, STUDY_LOGS[rule])

    def path(self, rule, name, **wildcards):
        """One output of one job: ``path("plane_table", "table", robot="CDPR4", pulley="SR")``."""
        return _join(self.folder, self.relative(rule, name, **wildcards))

    def relative(self, rule, name, **wildcards):
        """The same path relative to the results folder."""
        return STUDY_OUTPUTS[rule][name].format(**wildcards)

    def paths(self, rule, name, **fixed):
        """Output ``name`` of every job of ``rule`` whose wildcards agree with ``fixed``."""
        combos = [c for c in self.wildcards(rule) if all(str(c[k]) == str(v) for k, v in fixed.items())]
        return [self.path(rule, name, **c) for c in combos]

    def volume_shards(self, label):
        """The solver shards of one ``<robot>_<pulley>`` label (the volumes of one design)."""
        return [
            self.path("volume_shard", "table", **c)
            for c in self.wildcards("volume_shard")
            if f"{c['robot']}_{c['pulley']}" == label
        ]

    def rule_outputs(self, rule):
        """Every output of every job of ``rule``."""
        return [p for name in STUDY_OUTPUTS[rule] for p in self.paths(rule, name)]

    def targets(self):
        """Every file the study writes (shards included, logs not): what ``reproduce_paper`` asks for,
        so that any missing one is rebuilt."""
        return [p for rule in self.rules() for p in self.rule_outputs(rule)]

    def large_targets(self):
        """What ``make reproduce`` asks of a study with a ``sag`` section (the large study,
        workflow/rules/large.smk): the plane maps and paths of every robot, what sag adds along the
        path, the cables at the corner pose and the error budget when the study has a ``budget`` key
        (its RW_C box needs the DOE's workspace grids), not the DOE's index, maps, volumes, elasticity,
        winch and dead-length sections."""
        rules = (
            "plane_table",
            "plane_figure",
            "trajectory_table",
            "trajectory_figure",
            "sag_path",
            "sag_corner",
            "study_budget",
        )
        return [p for rule in rules for p in self.rule_outputs(rule)]

    def summary_inputs(self):
        """The tables the summary reads (``cdpr.pipeline.summary``): name -> path or list of paths."""
        out = {
            "winch": self.path("winch_table", "table"),
            "planes": self.paths("plane_table", "table"),
            "paths": self.paths("trajectory_table", "table"),
            "minmax": self.path("trajectory_figure", "table"),
            "volumes": self.path("volumes", "table"),
            "rw_c": self.path("regular_workspace", "json"),
            "doe": self.path("doe", "table"),
            "effects": self.path("doe", "effects"),
            "lines": self.path("maps", "lines"),
            "bands": self.path("elasticity", "bands"),
            "crossings": self.path("elasticity", "crossings"),
            "dead_length": self.path("dead_length", "table"),
            "uncertainty": [self.path("uncertainty", "bands"), self.path("uncertainty", "sobol")]
            if self.st.get("uncertainty")
            else [],
        }
        if self.st.get("budget"):  # the study's error budget (a spatial study with a `budget` key)
            out["budget"] = self.path("study_budget", "table")
        if self.st["volumes"].get("dphi_limits_rad"):  # R_V on δφ (a spatial study's volumes keys)
            out["volumes_dphi"] = self.path("volumes_dphi", "table")
        out.update(self._point_table_inputs())
        return out

    def _point_table_inputs(self):
        """The point tables behind the volumes and RW_C that a study of rigid platforms' summary also
        reads (``summary_rows.interference_rows``, ``summary_rows.reached_rows``): none for point masses."""
        if not any(not r.point_mass for r in (self.st.robot_models or {}).values()):
            return {}
        return {
            "volume_shards": self.paths("volume_shard", "table"),
            "workspace_grids": self.paths("workspace_grid", "table"),
        }

    def comparison_inputs(self):
        """The tables of this folder that the comparison of the two redundancy modes reads
        (``cdpr.pipeline.comparison``): summary, plane tables and the aggregated tables."""
        return (
            [self.path("summary", "table")]
            + self.paths("plane_table", "table")
            + [
                self.path("volumes", "table"),
                self.path("doe", "table"),
                self.path("doe", "effects"),
                self.path("maps", "lines"),
                self.path("elasticity", "bands"),
                self.path("elasticity", "crossings"),
                self.path("elasticity", "table"),
            ]
            + self.paths("trajectory_table", "table")  # the overlays of Fig. 10
            + self.paths("elasticity_path", "table")  # the overlays of Fig. 19
            + ([self.path("uncertainty", "bands")] if self.st.get("uncertainty") else [])
        )


def _flat(values):
    out = []
    for v in values:
        out += v if isinstance(v, list) else [v]
    return out


def missing(paths):
    """The paths among ``paths`` (a list, or a dict of paths and lists) that are not files."""
    paths = _flat(paths.values()) if isinstance(paths, dict) else _flat(paths)
    return [p for p in paths if not Path(p).is_file()]


def check_complete(folder, paths, what):
    """Raise CdprError naming the folder and the missing files when ``paths`` are not all there.

    Parameters
    ----------
    folder : str or Path
        The results folder (named in the message; checked to exist first).
    paths : list or dict
        The files needed (``Layout.summary_inputs`` ...).
    what : str
        Who needs them, for the message ("the summary").
    """
    if not Path(folder).is_dir():
        raise CdprError(f"{folder}: the results folder does not exist; run the study first")
    gone = missing(paths)
    if gone:
        shown = ", ".join(str(Path(p).relative_to(folder)) if _under(p, folder) else str(p) for p in gone[:5])
        more = f" and {len(gone) - 5} more" if len(gone) > 5 else ""
        raise CdprError(
            f"{folder}: incomplete results folder: {what} needs {len(gone)} missing file(s): {shown}{more}; "
            "run the study (snakemake) to write them"
        )


def _under(p, folder):
    try:
        Path(p).relative_to(folder)
        return True
    except ValueError:
        return False


class ComparisonLayout:
    """The files of a comparison (``config/comparisons/*.yaml``): its page, its folder, and the two
    study results folders it reads.

    Parameters
    ----------
    cmp : cdpr.pipeline.comparison.Comparison
        The validated comparison (``load_comparison``).
    """

    def __init__(self, cmp):
        self.cmp = cmp
        self.folder = str(cmp["folder"]).rstrip("/")
        self.page = str(cmp["page"])
        self.studies = {
            m: Layout(getattr(cmp, f"{m}_study"), cmp[m]["results"]) for m in ("paper", "physical")
        }

    def labels(self):
        """The designs of the error budget (``cdpr.pipeline.study.budget_designs``)."""
        return list(budget_designs(self.cmp.paper_study))

    def wildcards(self, rule):
        return _product(label=self.labels()) if rule == "budget_design" else [{}]

    def outputs(self, rule):
        return {
            name: pat.replace("{folder}", self.folder).replace("{page}", self.page)
            for name, pat in COMPARISON_OUTPUTS[rule].items()
        }

    def log(self, rule):
        return COMPARISON_LOGS[rule].replace("{folder}", self.folder)

    def paths(self, rule, name):
        """Output ``name`` of every job of ``rule``."""
        pat = COMPARISON_OUTPUTS[rule][name]
        return [pat.format(folder=self.folder, page=self.page, **c) for c in self.wildcards(rule)]

    def targets(self):
        """Every file the comparison writes: what ``reproduce_comparison`` asks for."""
        return [
            p
            for rule in COMPARISON_OUTPUTS
            for name in COMPARISON_OUTPUTS[rule]
            for p in self.paths(rule, name)
        ]

    def inputs(self):
        """The files of both studies' results folders that the comparison reads."""
        return [p for m in ("paper", "physical") for p in self.studies[m].comparison_inputs()]
