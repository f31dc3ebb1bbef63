"""cdpr.blas: the OpenBLAS kernels are pinned before numpy loads (the same bytes on every x86-64 CPU)."""

import os
import subprocess
import sys

import pytest

from cdpr import blas
from tests.conftest import ROOT

AVX2 = {"avx2", "fma", "sse2"}


def test_an_unset_variable_is_pinned_on_x86_64_with_avx2():
    env = {}
    assert blas.pin_openblas_core(env, "x86_64", AVX2) == "Haswell" and env == {
        "OPENBLAS_CORETYPE": "Haswell"
    }
    env = {}
    assert blas.pin_openblas_core(env, "AMD64", AVX2) == "Haswell"


def test_a_users_choice_and_other_cpus_are_left_alone():
    env = {"OPENBLAS_CORETYPE": "SkylakeX"}
    assert blas.pin_openblas_core(env, "x86_64", AVX2) == "SkylakeX" and env == {
        "OPENBLAS_CORETYPE": "SkylakeX"
    }
    for machine, flags in (("aarch64", AVX2), ("x86_64", {"sse2", "avx"}), ("x86_64", {"avx2"})):
        env = {}
        assert blas.pin_openblas_core(env, machine, flags) is None and env == {}


def test_cpu_flags_reads_the_flags_line(tmp_path):
    f = tmp_path / "cpuinfo"
    f.write_text("processor\t: 0\nflags\t\t: fpu sse2 avx2 fma\nbugs\t: x\n", encoding="utf-8")
    assert blas.cpu_flags(str(f)) == {"fpu", "sse2", "avx2", "fma"}
    assert blas.cpu_flags(str(tmp_path / "missing")) == set()


def _machine_pins():
    return sys.platform.startswith("linux") and blas.pin_openblas_core({}) == blas.CORETYPE


@pytest.mark.skipif(not _machine_pins(), reason="not an x86-64 Linux CPU with AVX2 and FMA")
def test_import_cdpr_makes_numpy_and_scipy_load_the_pinned_kernels():
    """OpenBLAS names the kernels it loads (OPENBLAS_VERBOSE=2): numpy's and scipy's, both Haswell,
    in a process that imports cdpr first and the variable unset."""
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    env["OPENBLAS_VERBOSE"] = "2"
    code = (
        "import cdpr, os, numpy, scipy.linalg; numpy.linalg.solve(numpy.eye(3), numpy.ones(3));"
        " scipy.linalg.lu_factor(numpy.eye(3)); print('env', os.environ['OPENBLAS_CORETYPE'])"
    )
    p = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr[-2000:]
    out = p.stdout + p.stderr
    cores = [ln.split(":", 1)[1].strip() for ln in out.splitlines() if ln.startswith("Core:")]
    assert "env Haswell" in out and len(cores) >= 1 and set(cores) == {"Haswell"}, out[-2000:]
