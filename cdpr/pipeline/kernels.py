"""Compile the numba kernels once, before a study runs (``cdpr compile``).

numba compiles a kernel the first time a process calls it and writes the machine code to its cache
(``cache=True``: ``cdpr/compiled/__pycache__``, or ``NUMBA_CACHE_DIR``); every later process loads
it in milliseconds. On a fresh clone the first jobs of a study each compile what they call, and two
studies started side by side (``make reproduce``) compile the same kernels twice at once. ``warm``
calls every kernel family the studies use on a few poses of the shipped robot families, so that the
compile is paid once, and split over the processes asked for (``part``): the studies then start on
a warm cache. It computes nothing a study keeps.

The families (``PARTS``): ``paper`` (the suspended point mass in paper mode: the 3-cable subsets,
their sensitivities, the uncertainty study's batched solves and linearised propagation),
``physical`` (the same in physical mode: the equilibrium on every cable), ``platform`` (the rigid
platform's pose solver and pose sensitivities, the tension distribution) and ``heavy`` (the
catenary, the heavy cables' equilibrium and inverse on a point mass and a rigid platform).
"""

from __future__ import annotations

import numpy as np

from cdpr.analyses import budget
from cdpr.analyses.compensation import compensate
from cdpr.analyses.uncertainty import PoseErrorModel
from cdpr.parameters import parameter_values
from cdpr.robot import load_robot, with_pulleys
from cdpr.solve import sensitivities, solve

#: The kernel families, in the order ``warm`` runs them (``part`` picks some).
PARTS = ("paper", "physical", "platform", "heavy")
#: Poses of the warm-up, as fractions of the anchors' box less 0.5 (``_poses``): near the top of the
#: frame; the kernels compile whatever the status of the pose.
_UNIT = np.array([[0.1, -0.1, 0.45], [-0.2, 0.15, 0.5]])


def _robots(path, name):
    """The shipped robot files of family ``name`` (the studies' robots): CDPR4 (point mass), CoGiRo
    with massless cables (rigid platform, ``cogiro_massless.yaml``), and both with heavy cables
    (cube50, CoGiRo's own file at 0.0631 kg/m)."""
    if name in ("paper", "physical"):
        return load_robot(path / "cdpr4.yaml")
    if name == "platform":
        return load_robot(path / "cogiro_massless.yaml")
    return [load_robot(path / "cube50.yaml"), load_robot(path / "cogiro.yaml")]


def _poses(robot):
    """Two poses from the anchors' bounding box (fractions ``0.5 + _UNIT`` of it per axis)."""
    lo, hi = robot.arrays.A.min(axis=0), robot.arrays.A.max(axis=0)
    return lo + (hi - lo) * (0.5 + _UNIT)


def _each_pulley(robot):
    """``robot`` with SR pulleys and with DR pulleys (a DR arm longer than its sheave's radius)."""
    c = robot.cables[0].pulley
    r_p = c.r_p if c.r_p > 0 else 0.05
    return [
        with_pulleys(robot, kind="SR", r_p=r_p),
        with_pulleys(robot, kind="DR", h=max(c.h, 1.5 * r_p), r_p=r_p),
    ]


def _uncertainty(r, p, threads, redundancy="physical", rotvec=None):
    """The uncertainty study's solves: full solves of two sampled robots (one batched pass), the
    linearisation and its propagation, in both cases."""
    theta = np.repeat(parameter_values(r)[None], 2, axis=0)
    theta[1] *= 1.0 + 1e-3
    for case in ("uncompensated", "compensated"):
        model = PoseErrorModel(r, p, case, redundancy, threads=threads, engine="compiled", rotvec=rotvec)
        model.solve(theta)
        lin = model.linearise()
        lin.dp(theta, threads=threads)
        lin.shift(theta, threads=threads)


def _point_mass(mode):
    def run(robot, threads):
        for r in _each_pulley(robot):
            p = _poses(r)
            solve(r, p, redundancy=mode, engine="compiled", threads=threads)
            sensitivities(r, p, redundancy=mode, engine="compiled", threads=threads)
            _uncertainty(r, p, threads, redundancy=mode)

    return run


def _platform(robot, threads):
    for r in _each_pulley(robot):
        p = _poses(r)
        sensitivities(r, p, np.zeros(3), redundancy="physical", engine="compiled", threads=threads)
        _uncertainty(r, p, threads, rotvec=np.zeros(3))
        budget.error_budget(r, p, threads=threads, rotvec=np.zeros(3), engine="compiled")


def _heavy(robots, threads):
    for robot in robots:
        for r in _each_pulley(robot):
            p = _poses(r)
            rv = None if r.point_mass else np.zeros(3)
            L0 = compensate(r, p, engine="compiled", rotvec=rv)["L0"]
            solve(r, p, rv, redundancy="physical", engine="compiled", threads=threads, L0=L0)


def warm(robots, part=PARTS, threads=None):
    """Compile (or load from numba's cache) every kernel family in ``part``.

    Parameters
    ----------
    robots : pathlib.Path
        The folder of the shipped robot files (``config/robots``: cdpr4, cogiro, cube50).
    part : sequence of str
        Members of ``PARTS``.
    threads : int, optional
        numba threads of the warm-up's solves (the compiled code does not depend on it).

    Returns
    -------
    list of str
        The families warmed, in order.
    """
    run = {
        "paper": _point_mass("paper"),
        "physical": _point_mass("physical"),
        "platform": _platform,
        "heavy": _heavy,
    }
    done = []
    for name in PARTS:
        if name in part:
            run[name](_robots(robots, name), threads)
            done.append(name)
    return done
