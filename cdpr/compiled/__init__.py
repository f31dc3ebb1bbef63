"""Numba twins of ``cdpr.models`` under the same module names (subsets, equilibrium, equilibrium6,
sensitivity, sensitivity6), tested equal to their references; ``_kernels`` holds the one scalar cable kernel they
share."""
