"""The numpy equilibrium of a suspended point mass with the point-mass keys: what ``cdpr.solve``
returns for such a robot from the numpy engine (``models.equilibrium.solve``, whose point-mass case
the compiled 3-DoF fast path ``cdpr.compiled.equilibrium.solve_points`` is tested against)."""

from cdpr.models import equilibrium
from cdpr.models.results import point_keys


def solve_physical(robot, p, **options):
    """``equilibrium.solve(robot, p, **options)`` with ``results.POINT_KEYS``."""
    return point_keys(equilibrium.solve(robot, p, **options))


def solve_physical_batch(robots, p, **options):
    """``equilibrium.solve_batch(robots, p, **options)`` with ``results.POINT_KEYS``."""
    return [point_keys(r) for r in equilibrium.solve_batch(robots, p, **options)]
