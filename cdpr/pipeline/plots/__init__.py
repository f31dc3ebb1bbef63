"""The figures of the study, one module per part of it, each function drawing one figure from tables.

Every function takes the tables (DataFrames) a pipeline job wrote beside the figure, draws, and
writes a PNG and a PDF (``style.save``). Nothing here computes physics: the numbers drawn are the
numbers in the tables. Figure numbers are those of Paty et al. 2021 (Fig. 9-19) and Métillon et
al. 2022 (Fig. 7).

Modules: ``style`` (colours, titles, the helpers every figure shares, ``save``), ``winch``
(Fig. 7), ``planes`` (Fig. 9, 12, tensions), ``trajectories`` (Fig. 10, 11), ``volumes``
(Fig. 13, 14), ``doe`` (Fig. 15, 16), ``maps`` (Fig. 17), ``elasticity`` (Fig. 18, 19),
``dead_length``, ``parity``, ``comparison`` (the two redundancy modes), ``budget`` (the error
budget), ``uq`` (the uncertainty study), ``calibration`` (the calibration studies) and ``robot``
(the robot in 3-D, the pulley-axis convention). Import the module of the part:
``from cdpr.pipeline.plots import planes``.
"""

import matplotlib

# every figure is drawn off screen: the backend is chosen before any module imports pyplot
matplotlib.use("Agg")
