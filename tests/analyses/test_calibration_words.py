"""The weak directions are named the same way on every machine (cdpr.analyses.calibration
identifiability / sparse_basis / direction_words): equal loadings are a tie broken by parameter
order, not by round-off."""

import numpy as np

from cdpr.analyses import calibration as cal

NAMES = [f"d_{i}" for i in range(1, 5)] + [f"offset_{i}" for i in range(1, 5)]


def _gauge_rows(rng, n=20):
    """Measurement rows that see d_i and offset_i only as their sum: null space d_i - offset_i, four
    directions whose loadings tie exactly (|d_i| = |offset_i| = 1/sqrt 2)."""
    return rng.standard_normal((n, 4)) @ np.hstack([np.eye(4), np.eye(4)])


def test_tied_null_directions_are_named_in_parameter_order_whatever_the_round_off():
    """Left-multiplying the rows by an orthogonal Q changes nothing mathematically (same singular
    values and null space) but changes the round-off of the SVD; LAPACK's pivoted QR then picked
    d_2, d_3 or d_1 first depending on it (16 orders out of 30 rotations before the fix)."""
    rng = np.random.default_rng(0)
    Jm = _gauge_rows(rng)
    expected = [f"d_{i} against offset_{i} (not seen by the data)" for i in range(1, 5)]
    for _ in range(30):
        Q, _ = np.linalg.qr(rng.standard_normal((20, 20)))
        ident = cal.identifiability(Q @ Jm, NAMES)
        assert ident["rank"] == 4
        assert ident["unidentified"] == expected


def test_sparse_basis_depends_only_on_the_row_space():
    """Any orthonormal basis of the null space gives the same sparse basis, rows in the same order."""
    rng = np.random.default_rng(1)
    B0 = np.hstack([np.eye(4), -np.eye(4)]) / np.sqrt(2)
    ref = cal.sparse_basis(B0)
    np.testing.assert_array_equal(np.abs(ref), np.abs(B0))
    for _ in range(20):
        M, _ = np.linalg.qr(rng.standard_normal((4, 4)))
        V = cal.sparse_basis(M @ B0)
        V *= np.sign(V[np.arange(4), np.arange(4)])[:, None]  # a row's sign is not a direction's name
        np.testing.assert_allclose(V, ref, atol=1e-12)


def test_direction_words_tie_goes_to_the_first_parameter():
    """Loadings equal to round-off: the first parameter leads, whichever one round-off made larger."""
    names = ["A_1_z", "A_2_z", "A_3_z"]
    for eps in (1e-13, -1e-13, 0.0):
        v = np.array([0.5 + eps, 0.5 - eps, -np.sqrt(0.5)])
        v /= np.linalg.norm(v)
        assert (
            cal.direction_words(v, names, 0.0, True) == "A_3_z against A_1_z and A_2_z (not seen by the data)"
        )
        w = np.array([0.6 - eps, -0.6 + eps, 0.1])  # A_1_z and A_2_z tie for the lead
        assert cal.direction_words(w, names, 0.5, False).startswith("A_1_z against A_2_z")


def test_a_weak_singular_value_reads_below_one():
    """'weak: s = ... < 1' never prints s = 1 (two digits round 0.996 up): the digits go down to
    the first that is not a 9, and what is printed is below 1 and within its last digit of s."""
    for s in (0.5, 0.123, 2.7e-5, 0.9949, 0.995, 0.996, 0.9996, 0.999999):
        text = cal.below_one(s)
        assert float(text) < 1.0 and abs(float(text) - s) < 0.05 * s
    assert cal.below_one(0.996) == "0.996" and cal.below_one(0.9996) == "0.9996"
    assert "s = 0.996 < 1" in cal.direction_words(np.array([1.0, 0.5]), ["a", "b"], 0.996, False)
