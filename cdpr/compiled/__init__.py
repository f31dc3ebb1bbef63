"""Numba twins of ``cdpr.models`` under the same module names (subsets, equilibrium, sensitivity,
sensitivity6), tested equal to their references; ``_kernels`` holds the one scalar cable kernel they
share, ``_linalg`` the small dense linear algebra, ``_point_mass`` the 3-DoF fast path of the
equilibrium for a suspended point mass."""
