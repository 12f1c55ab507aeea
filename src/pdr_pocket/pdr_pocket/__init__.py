"""Step-and-heading navigation for an IMU in the trouser pocket (Muñoz Díaz 2016).

In place, the orientation filter of chapter 3:

- :mod:`compiled_orientation`: the UKF's per-sample loop (numba), its equations;
- :mod:`orientation`: :class:`~orientation.OrientationFilter`, bulk and sample by sample,
  external yaw and z-bias corrections (Eq. (6.2));
- :mod:`config`: the YAML configuration (``config/pocket_pdr.yaml``);
- :mod:`magnetometer`: hard/soft-iron calibration and sphere coverage;
- :mod:`attitude_offline`: bag inputs, outputs and report of ``pdr-pocket attitude``;
- :mod:`streaming`: the live path; :mod:`nodes.pocket_pdr`: the node;
- :mod:`cli`: ``pdr-pocket``; :mod:`plots`: its figures.

Steps, activities, step length, stairs and the position filter come with the next issue.
"""
