"""The published models, as numpy references: one paper model per module (pulleys, inverse, statics,
direct, subsets, equilibrium, tension distribution, sensitivity, winch, drive) and what a solved point
is (results). Their compiled twins, under the same module names, are in ``cdpr.compiled``."""
