"""Foot-mounted strapdown INS with zero-velocity updates (papers 000, 001, 004).

The navigator, at the top of the package:

- :mod:`attitude_update`, :mod:`strapdown`: attitude increments and mechanization
  (000, section III-A; 001, Eqs. (3)–(5)).
- :mod:`zero_velocity`: the stance detectors behind one interface (000, Eqs. (15)–(19)).
- :mod:`zupt_ekf`, :mod:`compiled_filter`, :mod:`compiled_smoother`: the ZUPT/ZARU
  error-state EKF and the RTS smoother (001, Eqs. (6)–(9), Alg. 1).
- :mod:`config`: the YAML configuration; :mod:`offline`: whole bags;
  :mod:`streaming`: sample by sample; :mod:`nodes.zupt_ekf`: the ROS node.
- :mod:`cli`: ``pdr-ekf``; :mod:`plots`: its figures.

Research tooling (Monte-Carlo, closed-form error model, sweeps) lives in
:mod:`pdr_ins_ekf.studies`, which imports the navigator and never the reverse.
"""
