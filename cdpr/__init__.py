"""cdpr: pose errors of cable-driven parallel robots from pulleys, cable elasticity and winch geometry.

The public face: the names of ``__all__`` are what the README's quick start uses, re-exported from
the layer that defines them (``_EXPORTS``). They load on first use (a module ``__getattr__``,
PEP 562), so ``import cdpr`` itself imports neither numpy nor numba and ``cdpr --help`` stays quick. It
first pins the OpenBLAS kernels on x86-64 (``cdpr.blas``: the same bytes on every CPU).

    >>> import cdpr
    >>> robot = cdpr.load_robot("config/robots/cdpr4.yaml")        # doctest: +SKIP
    >>> cdpr.solve_table(robot, [[0.0, 0.0, 2.5]])                 # doctest: +SKIP
"""

from importlib import import_module

from cdpr.blas import pin_openblas_core

# Before anything loads numpy: the same OpenBLAS kernels on every x86-64 CPU (same bytes everywhere).
pin_openblas_core()

#: Public name -> the module that defines it.
_EXPORTS = {
    "CdprError": "cdpr.errors",
    "ConfigError": "cdpr.errors",
    "Robot": "cdpr.robot",
    "WinchParams": "cdpr.robot",
    "load_robot": "cdpr.robot",
    "robot_from_dict": "cdpr.robot",
    "with_pulleys": "cdpr.robot",
    "parameter_names": "cdpr.parameters",
    "parameter_values": "cdpr.parameters",
    "robot_with_parameters": "cdpr.parameters",
    "STATUSES": "cdpr.models.results",
    "L_TS": "cdpr.models.inverse",
    "igm_e": "cdpr.models.inverse",
    "degm_e": "cdpr.models.direct",
    "solve_points": "cdpr.models.subsets",
    "check_engine": "cdpr.solve",
    "solve_table": "cdpr.tables",
    "to_frame": "cdpr.tables",
    "sensitivities": "cdpr.solve",
    "subset_sensitivities": "cdpr.solve",
    "compensate": "cdpr.analyses.compensation",
    "compensated_pose": "cdpr.analyses.compensation",
    "trajectory": "cdpr.analyses.scans",
    "plane": "cdpr.analyses.scans",
    "ok_extremes": "cdpr.analyses.scans",
    "grid_points": "cdpr.analyses.workspace",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name):
    """Load a public name on first use (PEP 562) and keep it in the module's namespace."""
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version  # lazy: ~25 ms, never on --help

        try:
            value = version("cdpr")
        except PackageNotFoundError:  # a source tree that is not installed
            value = "0+unknown"
    elif name in _EXPORTS:
        value = getattr(import_module(_EXPORTS[name]), name)
    else:
        raise AttributeError(f"module 'cdpr' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted({*globals(), *__all__})
