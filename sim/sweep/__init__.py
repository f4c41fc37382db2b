"""Experiments over configurations × obstacles × seeds × packet loss (``rdcd sweep``).

The Python API for notebooks: ``load`` an experiment file, ``run`` it (optionally on a given
dask.distributed ``Client``), and read ``Results.rows()`` / ``Results.summary()``. Dask is imported
only when runs go to a cluster.
"""

from sim.sweep.api import MAX_RUNS, Results, SweepError, open_results, run
from sim.sweep.experiment import Experiment, ExperimentError, load

__all__ = ["MAX_RUNS", "Experiment", "ExperimentError", "Results", "SweepError", "load", "open_results",
           "run"]
