"""Study files (``config/studies/*.yaml``): reading, validation and the designs they define.

A study names its robots, the pulley designs to compare and the resolution of every analysis of
the paper. This module is the one place that reads a study: ``load_study`` applies the schema
``cdpr/schemas/study.schema.yaml`` and then the checks a schema cannot express (every robot file
readable and valid, every pulley design physically possible on every robot, sweeps increasing,
planes below the pulleys, ...), so that a bad value stops the run before any job, with one sentence
naming the study file, the key and what is allowed. The command line, the library and the
Snakemake pipeline all go through it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
from pathlib import Path

import numpy as np
import pandas as pd

from cdpr.analyses import doe
from cdpr.analyses.uncertainty import CASES, PARAMETER_KEYS, Distribution
from cdpr.analyses.workspace import BYTES_PER_POINT, check_box
from cdpr.errors import CdprError, ConfigError, raise_problems
from cdpr.robot import (
    TABLE1,
    check_pulley,
    load_robot,
    params_from_mapping,
    robot_from_dict,
    with_values,
    with_wrench,
)
from cdpr.validation import read_yaml, validate


@dataclasses.dataclass(frozen=True)
class SolverOptions:
    """How a study solves, read once from the study file by ``load_study``, each with its one default.

    Attributes
    ----------
    redundancy : str
        ``redundancy``: ``paper`` (the paper's 3-cable subset rule) or ``physical`` (the equilibrium
        on all cables).
    method : str
        ``solver``: the DEGM_E solver of every solve (``newton`` or ``fixed_point``).
    rotvec : tuple of float or None
        ``rotvec_rad``: the fixed platform orientation (3,) [rad] of every solve, None: the identity.
    wrench : tuple of float or None
        ``wrench``: the external wrench (6,) [N, N m] beside gravity on every robot of the study
        (``robot.with_wrench``), None: gravity alone.
    uq_redundancy : str
        ``uncertainty.redundancy``: the redundancy mode of the uncertainty study's uncompensated robot.
    """

    redundancy: str = "paper"
    method: str = "newton"
    rotvec: tuple | None = None
    uq_redundancy: str = "paper"
    wrench: tuple | None = None

    @classmethod
    def of(cls, mapping):
        """The options of a study mapping: its keys where given, else the defaults above."""
        u = mapping.get("uncertainty") or {}
        rv = mapping.get("rotvec_rad")
        return cls(
            redundancy=mapping.get("redundancy", cls.redundancy),
            method=mapping.get("solver", cls.method),
            rotvec=None if rv is None else tuple(float(x) for x in rv),
            uq_redundancy=u.get("redundancy", cls.uq_redundancy),
            wrench=None if mapping.get("wrench") is None else tuple(float(x) for x in mapping["wrench"]),
        )


class Study(dict):
    """A validated study: the parsed YAML mapping, plus ``path`` (the file it was read from),
    ``robot_models`` (the Robot of each ``robots`` key, as its file says, built once by the checks)
    and ``options`` (its :class:`SolverOptions`, read once)."""

    path: str = "<dict>"
    robot_models: dict = None
    _options: SolverOptions = None

    @property
    def options(self):
        """The study's :class:`SolverOptions` (read from the mapping the first time)."""
        if self._options is None:
            self._options = SolverOptions.of(self)
        return self._options


def load_study(path):
    """Read and validate a study file; returns a :class:`Study` (a dict of the YAML keys).

    Raises ConfigError naming the study file and the key for: a missing or malformed file, a schema
    violation, or a value the schema cannot check (``check_study``)."""
    data = read_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(path, None, f"expected a mapping of study keys, got {type(data).__name__}")
    if "truth_deviations" in data and "robots" not in data:
        raise ConfigError(
            path,
            None,
            "this is a calibration study (truth_deviations, no robots): run it with "
            "`cdpr calibrate study --study FILE`, not as a pipeline study",
        )
    if "data_sets" in data and "robots" not in data:
        raise ConfigError(
            path,
            None,
            "this is the Hangprinter study (data_sets, no robots): run it with "
            "`cdpr calibrate study --study FILE`, not as a pipeline study",
        )
    validate(data, "study", path)
    st = Study(data)
    st.path = str(path)
    _physical_by_default(st)
    st.setdefault("redundancy", SolverOptions.redundancy)
    check_study(st)
    return st


def _physical_by_default(st):
    """A study of a robot that is not a suspended point mass (a rigid platform, pulley axes other
    than +z, anchors not above the floor) or has heavy cables takes physical mode, that robot's only
    mode in a study, when it names none: ``redundancy`` and ``uncertainty.redundancy`` (when the section is there) left out become
    ``physical``, as the command line's default (``Robot.default_redundancy``). Paper mode asked for
    explicitly is refused by ``check_study`` as before. A robot file that is missing or invalid is
    left to ``check_study``, which reports it."""
    u = st.get("uncertainty")
    if "redundancy" in st and (not u or "redundancy" in u):
        return
    spatial = False
    for path in st["robots"].values():
        if not Path(path).is_file():
            continue
        try:
            robot = robot_from_dict(read_yaml(path), source=path)
            spatial = spatial or not robot.suspended_point_mass or robot.heavy
        except CdprError:
            continue
    if spatial:
        st.setdefault("redundancy", "physical")
        if u:
            u.setdefault("redundancy", "physical")


def check_results_folder(path, source="--config results", key="results"):
    """Refuse, in one line and before any job, a results folder that cannot be one: an existing
    file, or a path below an existing file.

    Parameters
    ----------
    path : str or Path
        The results folder (Snakemake's ``--config results=...``, or a study's ``conclusions.results``).
    source, key : str
        Where the path was given, for the message.

    Raises
    ------
    ConfigError
        When ``path`` or one of its parents is an existing file.
    """
    p = Path(path)
    for q in (p, *p.parents):
        if q.exists() and not q.is_dir():
            what = "is an existing file" if q == p else f"lies below {str(q)!r}, an existing file"
            raise ConfigError(
                source, key, f"the results folder {str(path)!r} {what}; give a folder (e.g. results/<study>)"
            )


def check_file(path, results=None):
    """The whole validation of a study file, as the pipeline makes it before any job, without
    Snakemake (``cdpr study check``): ``load_study``, and with ``results`` the results folder.

    Parameters
    ----------
    path : str or Path
        The study file.
    results : str or Path, optional
        The results folder the study would write (``check_results_folder``).

    Returns
    -------
    list of str
        One line per problem found (empty: the study is valid).
    """
    problems = []
    try:
        st = load_study(path)
    except ConfigError as exc:
        problems += [str(e) for e in getattr(exc, "problems", [exc])]
    else:
        ref = (st.get("conclusions") or {}).get("results")
        if ref is not None:
            try:
                check_results_folder(ref, str(path), "conclusions.results")
            except ConfigError as exc:
                problems.append(str(exc))
    if results is not None:
        try:
            check_results_folder(results)
        except ConfigError as exc:
            problems.append(str(exc))
    return problems


def height_range(robot):
    """The heights a study's plane, paths and points may take on ``robot``: (bottom [m], top [m], the
    top's name). A suspended point mass hangs between its floor and its lowest pulley; any other robot
    (a rigid platform, pulleys at any axis, anchors below the platform) stays within its frame box:
    from the floor (or its lowest anchor, if lower) to its highest anchor.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    tuple
        (bottom, top, where) with ``where`` "the lowest pulley" or "the highest anchor".
    """
    z = robot.A[:, 2]
    if robot.suspended_point_mass:
        return robot.floor_z, float(z.min()), "the lowest pulley"
    return min(robot.floor_z, float(z.min())), float(z.max()), "the highest anchor"


def redundancy(st):
    """The study's redundancy mode (``SolverOptions.redundancy``): ``paper`` (the paper's 3-cable
    subset rule, the default) or ``physical`` (the equilibrium on all cables, ``equilibrium``)."""
    return st.options.redundancy


def solve_kwargs(st, threads=None):
    """The keyword arguments of every solve a study runs (``scans``, ``solve_table``): method,
    threads, the redundancy mode and the fixed platform orientation (``rotvec_rad``, when set), from
    the study's :class:`SolverOptions`.

    Parameters
    ----------
    st : Study
        The validated study.
    threads : int, optional
        Threads of the compiled engine (None: all).

    Returns
    -------
    dict
    """
    o = st.options
    out = {"method": o.method, "threads": threads, "redundancy": o.redundancy}
    if o.rotvec is not None:
        out["rotvec"] = np.asarray(o.rotvec, dtype=float)
    return out


def uq_redundancy(st):
    """The redundancy mode of the uncertainty study's uncompensated robot
    (``SolverOptions.uq_redundancy``, key ``uncertainty.redundancy``)."""
    return st.options.uq_redundancy


def rotvec(st):
    """The study's fixed platform orientation ``rotvec_rad`` (3,) [rad], or None when the study does
    not set it (every solve then takes the identity: the solver's default for spatial robots)."""
    rv = st.options.rotvec
    return None if rv is None else list(rv)


def spatial_robots(st):
    """The keys of the study's robots that are not suspended point masses (a rigid platform with
    attachments, or pulley axes other than +z: ``Robot.suspended_point_mass``), solved in 6 DoF."""
    models = st.robot_models or {}
    return [k for k, r in models.items() if not r.suspended_point_mass]


def path_robot(st, label):
    """The robot key of the path ``label`` of ``trajectories.paths``: its ``robot`` key, by default
    the label itself (one path per robot, named after it)."""
    return st["trajectories"]["paths"][label].get("robot", label)


def uq_cases(st):
    """The uncertainty cases a study runs: ``uncompensated`` always; ``compensated`` (lengths
    compensated with the nominal model, then the robot in physical equilibrium) only when the
    study's uncompensated robot is physical too (``uncertainty.redundancy: physical``). The
    compensated robot is physical in every study, so a paper-mode study would only copy the
    physical study's tables: they are written once, by the physical study."""
    return CASES if uq_redundancy(st) == "physical" else CASES[:1]


def uq_spatial(st):
    """Whether the uncertainty study's robot (``doe.robot``) is solved as a pose (not a suspended
    point mass: ``analyses.uncertainty.PoseErrorModel``'s responses are ‖δp‖ and δφ, the figures
    have a δφ panel beside each ‖δp‖ one) rather than as a suspended point mass (‖δp‖ only)."""
    r = (st.robot_models or {}).get(st["doe"]["robot"])
    return r is not None and not r.suspended_point_mass


def robot_of(st, robot_key, **overrides):
    """The study's robot ``robot_key`` (the Robot its checks built, ``Study.robot_models``) with
    values set on it (``robot.with_values``: ``pulley``, ``h``, ``r_p``, ``dead_length``, ``E``,
    ``mass``); the robot file is not read again."""
    models = st.robot_models or {}
    robot = models.get(robot_key)
    if robot is None:  # a Study built by hand, without load_study's checks
        robot = with_wrench(load_robot(st["robots"][robot_key]), st.options.wrench, f"{st.path}: wrench")
    given = {k: v for k, v in overrides.items() if v is not None}
    return with_values(robot, **given) if given else robot


def design_robot(st, robot_key, pulley, E=None, dead_length=None):
    """Robot ``robot_key`` of the study with a pulley design {kind, h_m, r_p_m} on every cable, the
    study's dead length (or ``dead_length`` [m]) and optionally Young's modulus ``E`` [Pa], set as
    values on the study's Robot (``robot_of``)."""
    fixed = pulley["kind"] == "fixed"
    return robot_of(
        st,
        robot_key,
        pulley=pulley["kind"],
        h=None if fixed else pulley.get("h_m", 0.0),
        r_p=None if fixed else pulley.get("r_p_m", 0.0),
        dead_length=st["dead_length_m"] if dead_length is None else dead_length,
        E=E,
    )


def doe_tests(st):
    """The 2^3 tests of Table 2 (Paty 2021 section 4.2): number, coded levels and actual design."""
    lv = st["doe"]["levels"]
    X = doe.full_factorial(3)
    rows = []
    for i, (cj, ch, cr) in enumerate(X, start=1):
        rows.append(
            {
                "test": i,
                "joint_c": cj,
                "h_c": ch,
                "r_p_c": cr,
                "kind": lv["joint"][int(cj > 0)],
                "h_m": lv["h_m"][int(ch > 0)],
                "r_p_m": lv["r_p_m"][int(cr > 0)],
            }
        )
    return pd.DataFrame(rows)


def arange_incl(spec):
    """from, from + step, ..., to (inclusive) of a {from, to, step} mapping, rounded to 1e-10 m."""
    n = int(round((spec["to"] - spec["from"]) / spec["step"])) + 1
    return np.round(spec["from"] + spec["step"] * np.arange(n), 10)


def map_cells(st):
    """The (h, r_p) cells of the h-r_p maps (Fig. 17) with r_p < h [m]: the DR rule h > r_p, also
    used for SR so that both maps cover the same cells."""
    return [
        (float(h), float(r))
        for h in arange_incl(st["maps"]["h_m"])
        for r in arange_incl(st["maps"]["r_p_m"])
        if r < h - 1e-12
    ]


def map_kinds(st):
    """The pulley kinds of the h-r_p maps: the DOE's joint levels (SR and DR in the paper)."""
    return list(dict.fromkeys(st["doe"]["levels"]["joint"]))


def E_values(st):
    """Young's moduli [Pa] of the index-versus-E sweep (Fig. 18): ``steps`` evenly spaced moduli from
    ``from`` to ``to`` and the moduli of ``E_path_Pa`` (E_min, E_mean, E_max), sorted.

    E_mean (the cable's nominal modulus, 102.2 GPa in the paper) is always a point of the sweep, so
    that the index "at E_mean" of the summary is computed at E_mean, not at the nearest step (97.2 GPa
    for 8 steps from 67.2 to 137.2 GPa). A path modulus within 1e-9 (relative) of a step is that step.
    """
    e = st["elasticity"]
    sweep = [float(x) for x in np.linspace(e["E_Pa"]["from"], e["E_Pa"]["to"], e["E_Pa"]["steps"])]
    extra = [float(x) for x in e["E_path_Pa"] if not np.isclose(sweep, float(x), rtol=1e-9, atol=0).any()]
    return sorted(sweep + extra)


def volume_limits(st):
    """Error limits [m] of the R_V sweep (Fig. 14): the sweep and the paper's limits, sorted."""
    sw = st["volumes"]["sweep_m"]
    return sorted(
        set(np.round(np.linspace(sw["from"], sw["to"], sw["steps"]), 10)) | set(st["volumes"]["limits_m"])
    )


def dphi_volume_limits(st):
    """Orientation-error limits [rad] of the R_V sweep on δφ: ``volumes.dphi_sweep_rad`` and
    ``volumes.dphi_limits_rad``, sorted; [] when the study sets neither (no δφ volumes)."""
    v = st["volumes"]
    sw = v.get("dphi_sweep_rad")
    sweep = set(np.round(np.linspace(sw["from"], sw["to"], sw["steps"]), 12)) if sw else set()
    return sorted(float(x) for x in sweep | set(v.get("dphi_limits_rad") or []))


# ------------------------------------------------------------------------------------------------
# Checks a schema cannot express
# ------------------------------------------------------------------------------------------------
#: Points per second of ``cdpr grid`` (the measured 282,000-334,000 of benchmarks/README.md, rounded
#: down): the solver time a refused size would need.
POINTS_PER_SECOND = 250_000
#: Most shards a study key may ask for: each shard is a job of its own (a second of start-up or more).
MAX_SHARDS = 1000


def _memory():
    """This machine's memory [bytes]."""
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def _duration(seconds):
    for unit, size in (("days", 86400), ("hours", 3600), ("minutes", 60)):
        if seconds >= size:
            return f"{seconds / size:,.1f} {unit}"
    return f"{seconds:.1f} s"


def _check_grid(st, key, n, shards=None, jobs=1):
    """Refuse a grid of ``n``^3 points per job (``shards`` of it, if sharded) that cannot fit in this
    machine's memory, naming the memory and the solver time it needs; and a shard count above the
    points or above ``MAX_SHARDS``. ``jobs``: how many such grids the study solves (time only)."""
    points = n**3
    if shards is not None:
        skey = key.rsplit(".", 1)[0] + ".shards"
        if shards > points:
            raise ConfigError(
                st.path,
                skey,
                f"{shards} shards for {points:,} points ({key} = {n}, {n}^3): at most one shard per point",
            )
        if shards > MAX_SHARDS:
            raise ConfigError(st.path, skey, f"at most {MAX_SHARDS} shards (one job each), got {shards:,}")
    per_job = -(-points // (shards or 1))
    need, avail = per_job * BYTES_PER_POINT, _memory()
    if need > avail:
        raise ConfigError(
            st.path,
            key,
            f"{n}^3 = {points:,} points ({per_job:,} per job) would need about {need / 2**30:,.1f} GiB of memory "
            f"per job, more than this machine's {avail / 2**30:.1f} GiB, and about "
            f"{_duration(points * jobs / POINTS_PER_SECOND)} of solver time; use a smaller {key}"
            + (" or more shards" if shards is not None else ""),
        )


def check_sizes(st):
    """Refuse sizes that cannot run before any job (``_check_grid``), and a DOE whose two levels of
    a factor are equal (its 2^3 design could not tell the factor's effect)."""
    v, d, e, dl = st["volumes"], st["doe"], st["elasticity"], st["dead_length"]
    lv = d["levels"]
    for factor in ("joint", "h_m", "r_p_m"):
        a, b = lv[factor]
        if a == b:
            raise ConfigError(
                st.path,
                f"doe.levels.{factor}",
                f"the two levels must differ (the 2^3 design estimates each effect from their difference), got [{a}, {b}]",
            )
    n_designs = len(st["pulleys"]) * len(st["robots"])
    _check_grid(st, "volumes.n", v["n"], v["shards"], jobs=n_designs)
    _check_grid(st, "doe.workspace_n", d["workspace_n"], jobs=8)
    _check_grid(st, "doe.index_n", d["index_n"], jobs=8)
    _check_grid(st, "maps.index_n", st["maps"]["index_n"], jobs=len(map_cells(st)) * len(map_kinds(st)))
    moduli = len(E_values(st))
    if e["shards"] > moduli:
        raise ConfigError(
            st.path,
            "elasticity.shards",
            f"{e['shards']} shards for {moduli} moduli (elasticity.E_Pa and E_path_Pa): at most one shard per modulus",
        )
    _check_grid(st, "elasticity.index_n", e["index_n"], jobs=moduli * len(st["optimal"]))
    _check_grid(st, "dead_length.index_n", dl["index_n"], jobs=len(dl["values_m"]))
    u = st.get("uncertainty")
    if u:
        _check_grid(st, "uncertainty.monte_carlo.index_n", u["monte_carlo"]["index_n"])


def _increasing(st, key, lo, hi, what="'from' must be below 'to'"):
    if not lo < hi:
        raise ConfigError(st.path, key, f"{what}, got from = {lo:g}, to = {hi:g}")


def check_study(st):
    """Cross-key checks of a schema-valid study; raises ConfigError naming the study file and key.

    Every check runs, and all the problems found are reported in one error (``errors.raise_problems``): a study
    with several mistakes (a robot renamed in one place but not in the others) is corrected in one
    go."""
    src = st.path
    problems = []
    with _collect(problems):
        if redundancy(st) == "physical" and st.options.method != "newton":
            raise ConfigError(
                src,
                "solver",
                f"physical mode (redundancy: physical) has one solver, newton; got {st['solver']!r}",
            )
    robots = {}
    for key, path in st["robots"].items():
        with _collect(problems):
            if not Path(path).is_file():
                raise ConfigError(
                    src,
                    f"robots.{key}",
                    f"robot file {path!r} does not exist (paths are relative to the directory snakemake runs in)",
                )
            try:
                robots[key] = robot_from_dict(read_yaml(path), source=path)
            except ConfigError as exc:
                raise ConfigError(src, f"robots.{key}", f"robot file is invalid: {exc}") from None
            try:
                robots[key] = with_wrench(robots[key], st.options.wrench, f"robot {key}")
            except CdprError as exc:
                raise ConfigError(src, "wrench", str(exc)) from None
    known = list(st["robots"])  # a robot whose file is bad is reported once, above
    with _collect(problems):
        if st["doe"]["robot"] not in known:
            raise ConfigError(
                src, "doe.robot", f"unknown robot {st['doe']['robot']!r}; allowed: {', '.join(known)}"
            )
    ref = st.get("conclusions")
    if ref:
        with _collect(problems):
            if not Path(ref["study"]).is_file():
                raise ConfigError(
                    src, "conclusions.study", f"reference study {ref['study']!r} does not exist"
                )
            if Path(ref["study"]).resolve() == Path(src).resolve():
                raise ConfigError(
                    src, "conclusions.study", "the reference study is this study; name another one"
                )
    for key in st["trajectories"]["paths"]:
        with _collect(problems):
            if path_robot(st, key) not in known:
                sub = "" if path_robot(st, key) == key else ".robot"
                raise ConfigError(
                    src,
                    f"trajectories.paths.{key}{sub}",
                    f"unknown robot {path_robot(st, key)!r}; allowed: {', '.join(known)} "
                    "(a path's label is its robot's key unless it names one with `robot`)",
                )
    for sec in ("pulleys", "optimal"):
        for name, p in st[sec].items():
            if p["kind"] == "fixed":
                continue
            with _collect(problems):
                check_pulley(p["kind"], p.get("h_m", 0.0), p.get("r_p_m", 0.0), src, f"{sec}.{name}")
    lv = st["doe"]["levels"]
    with _collect(problems):
        for i, kind in enumerate(lv["joint"]):
            for h in lv["h_m"]:
                for r in lv["r_p_m"]:
                    check_pulley(kind, h, r, src, "doe.levels")
    before = len(problems)
    for key, spec in (("maps.h_m", st["maps"]["h_m"]), ("maps.r_p_m", st["maps"]["r_p_m"])):
        with _collect(problems):
            _increasing(st, key, spec["from"], spec["to"])
    with _collect(problems):
        if len(problems) == before and not map_cells(st):  # (a reversed range is the reason already)
            raise ConfigError(src, "maps", "no map cell has r_p < h; widen maps.h_m or lower maps.r_p_m")
    e = st["elasticity"]["E_Pa"]
    with _collect(problems):
        if not e["from"] > 0:
            raise ConfigError(
                src, "elasticity.E_Pa.from", f"Young's modulus must be > 0 Pa, got {e['from']:g}"
            )
        _increasing(st, "elasticity.E_Pa", e["from"], e["to"])
    sw = st["volumes"]["sweep_m"]
    with _collect(problems):
        _increasing(st, "volumes.sweep_m", sw["from"], sw["to"])
    sw = st["volumes"].get("dphi_sweep_rad")
    if sw:
        with _collect(problems):
            _increasing(st, "volumes.dphi_sweep_rad", sw["from"], sw["to"])
    with _collect(problems):
        check_sizes(st)
    with _collect(problems):
        try:
            check_box(st["doe"]["paper_rw_c_m"])
        except Exception as exc:
            raise ConfigError(src, "doe.paper_rw_c_m", str(exc)) from None
    w = st["winch"]
    before = len(problems)
    for k in ("lpm_from_m", "lpm_to_m"):
        with _collect(problems):
            if not math.isfinite(w[k]) or w[k] < 0:
                raise ConfigError(src, f"winch.{k}", f"must be a finite length >= 0 m, got {w[k]!r}")
    with _collect(problems):
        if len(problems) == before:  # a NaN or negative length is the reason already
            _increasing(st, "winch", w["lpm_from_m"], w["lpm_to_m"], "'lpm_from_m' must be below 'lpm_to_m'")
    z = st["plane"]["z_m"]
    for key, robot in robots.items():
        bottom, top, where = height_range(robot)
        with _collect(problems):
            if not bottom <= z < top:
                raise ConfigError(
                    src,
                    "plane.z_m",
                    f"must lie between the floor and {where} of robot {key} ({bottom:g} <= z < {top:g} m), got {z:g}",
                )
    for key, path in st["trajectories"]["paths"].items():
        if path_robot(st, key) not in robots:
            continue  # unknown or invalid robot: reported above
        _, top, where = height_range(robots[path_robot(st, key)])
        for end in ("start_m", "end_m"):
            with _collect(problems):
                if path[end][2] > top:
                    raise ConfigError(
                        src,
                        f"trajectories.paths.{key}.{end}",
                        f"z must not exceed {where} ({top:g} m), got {path[end][2]:g}",
                    )
    for problem in check_spatial_study(st, robots):
        problems.append(problem)
    if st.get("budget") is not None:
        with _collect(problems):
            budget_drum(st)
        with _collect(problems):
            budget_linear_density(st)
    if "uncertainty" in st and not problems:
        with _collect(problems):
            check_uncertainty(st, robots)
    raise_problems(src, problems)
    st.robot_models = robots
    return st


def check_spatial_study(st, robots):
    """The problems of a study with spatial robots (``Robot.suspended_point_mass`` false: a rigid
    platform or tilted pulley axes, solved in 6 DoF by ``equilibrium.solve``): a study runs
    such a robot in physical mode only (paper mode and its "best 3 of m" rule are the point-mass
    rule; the library and ``cdpr point``/``grid`` take it on a point mass with tilted axes, a study's
    jobs on suspended point masses only), is
    not scored against the papers (``paper_comparison``), runs the uncertainty study in physical
    mode only (``uq``: ‖δp‖ and δφ of the 6-DoF equilibrium); and
    ``rotvec_rad`` (the platform orientation) and ``budget`` (the error budget of a rigid platform,
    on the DOE robot) apply to spatial robots only, and the volumes on δφ (``volumes.dphi_limits_rad``,
    ``volumes.dphi_sweep_rad``) to robots with a rigid platform only (a point mass has no δφ).

    Parameters
    ----------
    st : Study
    robots : dict
        Robot key -> Robot of the study's valid robot files.

    Returns
    -------
    list of ConfigError
        One per key, each one sentence naming the key and what is allowed.
    """
    src = st.path
    spatial = [k for k, r in robots.items() if not r.suspended_point_mass]
    point = [k for k, r in robots.items() if r.suspended_point_mass]
    out = []
    if spatial:
        names = ", ".join(spatial)
        what = f"robot {names} is spatial (a rigid platform or pulley axes other than +z)"
        if redundancy(st) != "physical":
            out.append(
                ConfigError(
                    src,
                    "redundancy",
                    f"{what}: paper mode (the best 3 of m cables) is the point-mass rule, run by a study on "
                    f"suspended point masses only; use redundancy: physical, got {redundancy(st)!r}",
                )
            )
        u = st.get("uncertainty")
        if u and uq_redundancy(st) != "physical":
            out.append(
                ConfigError(
                    src,
                    "uncertainty.redundancy",
                    f"{what}: paper mode (the best 3 of m cables) is the point-mass rule, run by a study on "
                    f"suspended point masses only; use uncertainty.redundancy: physical, got {uq_redundancy(st)!r}",
                )
            )
        if st.get("paper_comparison"):
            out.append(
                ConfigError(
                    src,
                    "paper_comparison",
                    f"{what}: the papers' numbers are for their point-mass robots CDPR3 and CDPR4; "
                    "use paper_comparison: false (the summary lists our numbers, not scored)",
                )
            )
    doe_robot = robots.get(st["doe"]["robot"])
    budget_paper = st.get("redundancy", SolverOptions.redundancy) == "paper"
    if (
        st.get("budget") is not None
        and doe_robot is not None
        and doe_robot.suspended_point_mass
        and budget_paper
    ):
        out.append(
            ConfigError(
                src,
                "budget",
                f"the study's error budget solves the physical equilibrium; robot {st['doe']['robot']} (doe.robot) "
                "is a point mass in a paper-mode study: set redundancy: physical, or remove the key (a paper-mode "
                "point-mass study has the comparison's budget, config/comparisons/*.yaml)",
            )
        )
    out += _sag_problems(st, src, robots)
    params = (st.get("uncertainty") or {}).get("parameters") or {}
    for key in ("attachment_offset_m", "com_offset_m"):
        if key in params and doe_robot is not None and doe_robot.point_mass:  # no b, c in its θ
            out.append(
                ConfigError(
                    src,
                    f"uncertainty.parameters.{key}",
                    f"a rigid platform's parameter (attachments b_i, centre of mass c); robot {st['doe']['robot']} "
                    "(doe.robot) is a point mass, whose uncertainty study draws young_modulus_Pa, "
                    "h_offset_m, r_p_offset_m, dead_length_offset_m, anchor_offset_m and mass_kg: remove the key",
                )
            )
    masses = [k for k, r in robots.items() if r.point_mass]
    for key in ("dphi_limits_rad", "dphi_sweep_rad"):
        if st["volumes"].get(key) is not None and masses:
            out.append(
                ConfigError(
                    src,
                    f"volumes.{key}",
                    f"the error-limited volumes on δφ need an orientation; robot {', '.join(masses)} is a "
                    "point mass (no δφ): remove the key or use spatial robots only",
                )
            )
    if st.get("rotvec_rad") is not None and point:
        out.append(
            ConfigError(
                src,
                "rotvec_rad",
                f"the platform orientation applies to spatial robots only; robot {', '.join(point)} "
                "is a point mass (no orientation): remove rotvec_rad or use spatial robots only",
            )
        )
    return out


def budget_drum(st):
    """The drum of the study's error budget (``budget.drum``, Métillon 2022 Table 1 keys; missing
    keys and a study without the key take Table 1's drum): the winch entries put it on every cable
    that has no winch of its own.

    Parameters
    ----------
    st : Study

    Returns
    -------
    WinchParams

    Raises
    ------
    ConfigError
        Naming ``budget.drum.<key>`` for an unknown key or a value out of range.
    """
    drum = (st.get("budget") or {}).get("drum")
    return TABLE1 if drum is None else params_from_mapping(drum, st.path, "budget.drum")


def budget_linear_density(st):
    """The cables' linear density of the study's error budget (``budget.linear_density_kg_m``
    [kg/m], mass per unstrained metre; issue 38): set on the budget's designs, so that a value > 0
    adds the budget's ``sag`` effect (``analyses.budget.effects_of``). None when the study does not
    give it: the designs keep their robot file's ``cable.linear_density_kg_m``. The other analyses
    of the study never read it.

    Parameters
    ----------
    st : Study

    Returns
    -------
    float or None [kg/m]

    Raises
    ------
    ConfigError
        Naming ``budget.linear_density_kg_m`` for a value that is not a finite number >= 0.
    """
    rho = (st.get("budget") or {}).get("linear_density_kg_m")
    if rho is None:
        return None
    if isinstance(rho, bool) or not isinstance(rho, (int, float)) or not math.isfinite(rho) or rho < 0:
        raise ConfigError(
            st.path,
            "budget.linear_density_kg_m",
            f"a mass per metre in kg/m, a finite number >= 0, got {rho!r}",
        )
    return float(rho)


@contextlib.contextmanager
def _collect(problems):
    """Run one check; a ConfigError it raises joins ``problems`` instead of stopping the others."""
    try:
        yield
    except ConfigError as exc:
        problems.append(exc)


def check_uncertainty(st, robots):
    """Cross-key checks of the ``uncertainty`` section (``cdpr.analyses.uncertainty``): designs among
    ``optimal``, each distribution's keys and range, the varied keys declared, sample counts, Sobol
    points inside the frame; and the distributions' support checked against the physics of every
    design (moduli and mass > 0, pulley rule, dead lengths >= 0) where it is bounded."""
    src, u = st.path, st["uncertainty"]
    for i, d in enumerate(u["designs"]):
        if d not in st["optimal"]:
            raise ConfigError(
                src, f"uncertainty.designs[{i}]", f"unknown design {d!r}; allowed: {', '.join(st['optimal'])}"
            )
    for key, spec in u["parameters"].items():
        k = f"uncertainty.parameters.{key}"
        need = {"uniform": ("low", "high"), "normal": ("mean", "sd")}[spec["dist"]]
        missing = [n for n in need if n not in spec]
        if missing:
            raise ConfigError(
                src, f"{k}.{missing[0]}", f"a {spec['dist']} distribution needs {' and '.join(need)}"
            )
        if spec["dist"] == "uniform" and ("mean" in spec or "sd" in spec):
            raise ConfigError(src, k, "a uniform distribution takes low and high only (no mean, sd)")
        if "low" in spec and "high" in spec and not spec["low"] < spec["high"]:
            raise ConfigError(
                src, k, f"'low' must be below 'high', got low = {spec['low']:g}, high = {spec['high']:g}"
            )
        if spec["dist"] == "normal" and not spec.get("low", -math.inf) < spec["mean"] < spec.get(
            "high", math.inf
        ):
            raise ConfigError(
                src, f"{k}.mean", "the mean of a truncated normal must lie between low and high"
            )
        if key == "mass_kg" and "per_cable" in spec:
            raise ConfigError(
                src, f"{k}.per_cable", "the payload mass is one parameter; per_cable does not apply"
            )
        lo, _ = Distribution.from_spec(spec).support()
        group, kind = PARAMETER_KEYS[key]
        if kind == "value" and not lo > 0:
            raise ConfigError(
                src,
                k,
                f"must be bounded above 0 (low > 0, or a normal truncated by low > 0), got lowest value {lo:g}",
            )
    mc = u["monte_carlo"]
    for i, key in enumerate(mc["vary"]):
        if key not in u["parameters"]:
            raise ConfigError(
                src,
                f"uncertainty.monte_carlo.vary[{i}]",
                f"{key!r} has no distribution in uncertainty.parameters; declared: {', '.join(u['parameters'])}",
            )
    if mc["full_samples"] > mc["samples"]:
        raise ConfigError(
            src,
            "uncertainty.monte_carlo.full_samples",
            f"must not exceed samples ({mc['samples']}): the full solves check the first samples, got {mc['full_samples']}",
        )
    if mc["shards"] > mc["full_samples"]:
        raise ConfigError(
            src,
            "uncertainty.monte_carlo.shards",
            f"must not exceed full_samples ({mc['full_samples']}), got {mc['shards']}",
        )
    b = u["sobol"]["base_samples"]
    if b & (b - 1):
        raise ConfigError(
            src, "uncertainty.sobol.base_samples", f"must be a power of 2 (Sobol' sequence), got {b}"
        )
    _, top, where = height_range(robots[st["doe"]["robot"]])
    for i, pnt in enumerate(u["sobol"]["points_m"]):
        if not pnt[2] < top:
            raise ConfigError(
                src,
                f"uncertainty.sobol.points_m[{i}]",
                f"z must lie below {where} ({top:g} m), got {pnt[2]:g}",
            )
    _check_offsets(st, u["parameters"])


def _check_offsets(st, params):
    """The bounded offsets of h, r_p and d keep every design physical (pulley rule, d >= 0)."""

    def span(key):
        if key not in params:
            return 0.0, 0.0
        return Distribution.from_spec(params[key]).support()

    (h_lo, _), (_, r_hi), (d_lo, _) = span("h_offset_m"), span("r_p_offset_m"), span("dead_length_offset_m")
    for dk in st["uncertainty"]["designs"]:
        p = st["optimal"][dk]
        h, r = p.get("h_m", 0.0), p.get("r_p_m", 0.0)
        if p["kind"] != "fixed" and h > 0 and np.isfinite(h_lo) and np.isfinite(r_hi):
            try:
                check_pulley(p["kind"], h + h_lo, r + r_hi, st.path, f"uncertainty.parameters (design {dk})")
            except ConfigError as exc:
                raise ConfigError(
                    st.path,
                    "uncertainty.parameters.h_offset_m",
                    f"the lowest h and the highest r_p of design {dk} break the pulley rule: {exc}",
                ) from None
        if np.isfinite(d_lo) and st["dead_length_m"] + d_lo < 0:
            raise ConfigError(
                st.path,
                "uncertainty.parameters.dead_length_offset_m",
                f"the lowest dead length {st['dead_length_m'] + d_lo:g} m is negative",
            )


def budget_designs(st):
    """The designs of the error budget: label -> (robot key, pulley design {kind, h_m, r_p_m}): every
    robot x pulley design of the study, and the optimal designs on the DOE robot."""
    out = {f"{rk}_{pk}": (rk, spec) for rk in st["robots"] for pk, spec in st["pulleys"].items()}
    out.update(
        {f"{st['doe']['robot']}_{dk}": (st["doe"]["robot"], spec) for dk, spec in st["optimal"].items()}
    )
    return out


def _sag_problems(st, src, robots):
    """The ``sag`` section's checks (issue 38, ``cdpr.pipeline.sag``): its robots are study robots,
    ``robot`` with heavy cables and ``massless`` without, and each has a path in ``trajectories``."""
    sg = st.get("sag")
    if not sg:
        return []
    out = []
    for key, heavy in (("robot", True), ("massless", False)):
        name = sg[key]
        if name not in st["robots"]:
            out.append(
                ConfigError(src, f"sag.{key}", f"unknown robot {name!r}; allowed: {', '.join(st['robots'])}")
            )
            continue
        r = robots.get(name)
        if r is not None and bool(r.heavy) != heavy:
            want = (
                "heavy cables (cable.linear_density_kg_m > 0)"
                if heavy
                else "massless cables (linear_density_kg_m: 0)"
            )
            out.append(ConfigError(src, f"sag.{key}", f"robot {name!r} must have {want}"))
        if not any(path_robot(st, k) == name for k in st["trajectories"]["paths"]):
            out.append(ConfigError(src, f"sag.{key}", f"robot {name!r} has no path in trajectories.paths"))
    return out
