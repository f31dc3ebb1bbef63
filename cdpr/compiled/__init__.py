"""Numba twins of ``cdpr.models`` under the same module names (subsets, equilibrium,
sensitivity), tested equal to their references; ``_kernels`` holds the one scalar cable kernel they
share, ``_linalg`` the small dense linear algebra, ``_pose_sensitivity`` the pose sensitivities
(``sensitivity`` exposes them), ``_point_mass`` the 3-DoF fast path of the
equilibrium for a suspended point mass."""
