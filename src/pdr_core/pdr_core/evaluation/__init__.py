"""Scores against a truth, figures and batch runs: what the offline tools, the studies and
the benchmarks use, and no navigator imports (test/test_code_shape.py).

Modules:
    metrics           Trajectory error metrics: the report.json fields (docs/reports.md).
    consistency       NEES of position and attitude against a truth: is the covariance
                      honest?
    attitude_metrics  Attitude errors against a truth, one definition for every tool that
                      reports them.
    plot_layout       Titles, top views and height axes shared by every PNG.
    parallel          Parallel work on a Dask cluster, and runs that do not depend on how
                      they are split.
"""
