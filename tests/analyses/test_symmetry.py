"""Symmetric grids: one solve per orbit gives the full grid's ‖δp‖ and statuses (both modes)."""

import dataclasses

import numpy as np
import pytest

from cdpr.analyses.symmetry import D4, grid_symmetries, orbits, solve_grid
from cdpr.robot import with_pulleys

RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


def test_group_of_cdpr4_cdpr3_and_a_broken_symmetry(cdpr4, cdpr3):
    assert len(grid_symmetries(cdpr4, RW_C)) == 8
    assert len(grid_symmetries(cdpr4, [-2.32, 2.32, -2.0, 2.0, 0.0, 3.73])) == 4  # no diagonal: not square
    assert len(grid_symmetries(cdpr4, [-2.0, 2.32, -2.32, 2.32, 0.0, 3.73])) == 2  # only y -> -y
    frame3 = [-2.5, 2.5, -1.4433756729740643, 2.886751345948129, 0.0, 5.0]
    assert len(grid_symmetries(cdpr3, frame3)) == 2  # identity and x -> -x
    c = list(cdpr4.cables)
    c[0] = dataclasses.replace(c[0], dead_length=3.0)
    odd = dataclasses.replace(cdpr4, cables=tuple(c))
    assert [t.tolist() for t in grid_symmetries(odd, RW_C)] == [D4[0].tolist(), [[0, 1], [1, 0]]]


@pytest.mark.parametrize("n", [1, 4, 7])
def test_orbits_partition_the_grid(n):
    reps, inverse = orbits(n, list(D4))
    assert inverse.shape == (n**3,) and (reps[inverse] <= np.arange(n**3)).all()
    assert len(reps) == len(np.unique(reps))
    k = n // 2  # orbit sizes under D4 on a square layer: 1, 4 or 8 -> solved share about 1/8
    assert len(reps) == n * (((n + 1) // 2) * ((n + 1) // 2 + 1) // 2 if n % 2 else k * (k + 1) // 2)


@pytest.mark.parametrize("kind", ["SR", "DR"])
@pytest.mark.parametrize("redundancy", ["paper", "physical"])
def test_symmetric_solve_equals_the_full_grid(cdpr4, kind, redundancy):
    robot = with_pulleys(cdpr4, kind=kind, h=0.1, r_p=0.0665)
    box = [-2.6, 2.6, -2.6, 2.6, 0.0, 4.9]  # reaches outside the frame: every status appears
    d1, s1, k1 = solve_grid(robot, box, 11, symmetric=False, redundancy=redundancy)
    d2, s2, k2 = solve_grid(robot, box, 11, redundancy=redundancy)
    assert k1 == 11**3 and k2 == 11 * 21
    assert (s1 == s2).all() and len(set(s1)) > 1
    ok = s1 == "ok"
    np.testing.assert_allclose(d2[ok], d1[ok], rtol=0, atol=1e-12)


def test_commanded_lengths_refused(cdpr4):
    with pytest.raises(ValueError, match="L0"):
        solve_grid(cdpr4, RW_C, 3, redundancy="physical", L0=np.ones(4))
