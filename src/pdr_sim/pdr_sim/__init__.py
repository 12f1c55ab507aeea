"""Foot-mounted IMU simulator, bag playback and recording, and the ``pdr-sim`` CLI.

Data flow: scenario (:mod:`scenario`) -> trajectory model (:mod:`foot_trajectory`, step
patterns of :mod:`step_pattern`) -> true signals (:mod:`signals`) -> sensor errors
(:mod:`pdr_core.imu_errors`) -> message batches (:mod:`simulation`) -> bag (``pdr-sim
generate``) or the live graph (:mod:`nodes.imu_sim`). :mod:`step_fit` fits step patterns
to recorded feet; :mod:`allan_report` and :mod:`plots` make the tables and figures.
"""
