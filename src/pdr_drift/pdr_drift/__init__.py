"""Landmark detection, revisit recognition and heading-drift corrections (Muñoz Díaz
2016, chapter 5).

- :mod:`corners`: corners from the step headings, and the angle helpers;
  :mod:`landmarks`: corner and stair landmarks and their association (χ² gate).
- :mod:`drift`: the heading drift from a revisit, and offline from all of them (Eq. (6.5)).
- :mod:`estimator`: :class:`~estimator.DriftEstimator`, step by step: landmarks,
  associations, drifts and the yaw and gyro-bias corrections to send.
- :mod:`config`: the YAML configuration; :mod:`streaming`: the live path;
  :mod:`nodes.landmark_drift`: the node.
- :mod:`offline`: ``pdr-drift run`` on a bag of steps; :mod:`cli`: ``pdr-drift``;
  :mod:`plots`: its figures.
- :mod:`drift_log`: what the estimator did over a walk; :mod:`drift_report`: that against
  the simulator's truth, for ``pdr-pocket run --drift``.
"""
