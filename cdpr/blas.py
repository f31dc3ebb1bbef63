"""One BLAS kernel family on every x86-64 machine, so that the same config gives the same bytes.

numpy's and scipy's wheels bundle OpenBLAS built for many CPUs (``DYNAMIC_ARCH``): at load, each
picks the kernels of the CPU it runs on (``SkylakeX`` on an Intel Sapphire Rapids, ``Zen`` on an AMD
EPYC, ...). The kernels sum in different orders, so a linear solve, an eigenvalue or a least-squares
step differs in its last bits from one CPU to the next, and where a result is sensitive to them (a
Newton restart decided by a threshold, a Sobol index from differences of near-equal sums) the
12 digits we write differ too: the CoGiRo study's Sobol indices differed at the 12th digit and its
dominant-parameter map at the 9th between an AMD EPYC and an Intel Xeon, and were identical with
both machines on the ``Haswell`` kernels.

``pin_openblas_core`` sets ``OPENBLAS_CORETYPE=Haswell`` (AVX2 and FMA kernels, which every x86-64
CPU since 2013-2015 runs) before numpy is imported: ``cdpr/__init__.py`` calls it, so every
``cdpr`` command and every pipeline job use the same kernels. It only fills an unset variable (a
user's own choice stays) and leaves other CPUs (ARM, or x86-64 without AVX2) alone. A script that
imports numpy before cdpr has its machine's kernels: set ``OPENBLAS_CORETYPE=Haswell`` in its
environment to get the pipeline's bytes. Standard library only (it runs before numpy).
"""

import os
import platform

#: The OpenBLAS kernel family used on x86-64 (``OPENBLAS_CORETYPE``).
CORETYPE = "Haswell"
#: CPU flags (``/proc/cpuinfo``) the ``Haswell`` kernels need.
NEEDS = ("avx2", "fma")


def cpu_flags(path="/proc/cpuinfo"):
    """The CPU's feature flags as listed by ``path`` (Linux), an empty set where it cannot be read.

    Parameters
    ----------
    path : str
        The cpuinfo file.

    Returns
    -------
    set of str
    """
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("flags"):
                    return set(line.partition(":")[2].split())
    except OSError:
        pass
    return set()


def pin_openblas_core(environ=None, machine=None, flags=None):
    """Set ``OPENBLAS_CORETYPE`` to ``CORETYPE`` in ``environ`` where it is unset, the machine is
    x86-64 and its CPU has ``NEEDS``; it takes effect for the OpenBLAS libraries loaded afterwards
    (numpy's and scipy's) and in every child process.

    Parameters
    ----------
    environ : mutable mapping, optional
        Default ``os.environ``.
    machine : str, optional
        Default ``platform.machine()``.
    flags : set of str, optional
        Default ``cpu_flags()``.

    Returns
    -------
    str or None
        The value of ``OPENBLAS_CORETYPE`` in effect afterwards (None: unset).
    """
    environ = os.environ if environ is None else environ
    if "OPENBLAS_CORETYPE" not in environ:
        machine = platform.machine() if machine is None else machine
        if machine.lower() in ("x86_64", "amd64"):
            flags = cpu_flags() if flags is None else flags
            if all(f in flags for f in NEEDS):
                environ["OPENBLAS_CORETYPE"] = CORETYPE
    return environ.get("OPENBLAS_CORETYPE")
