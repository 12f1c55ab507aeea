"""Foot-mounted strapdown INS with zero-velocity updates (Zampella et al. 2011; Simón
Colomar et al. 2012; Wang et al. 2020).

The navigator, at the top of the package:

- :mod:`attitude_update`, :mod:`strapdown`: attitude increments and mechanization
  (Zampella et al. 2011, section III-A; Simón Colomar et al. 2012, Eqs. (3)–(5)).
- :mod:`zero_velocity`: the stance detectors behind one interface (Zampella et al. 2011,
  Eqs. (15)–(19); SHOE, Wang et al. 2020, section II).
- :mod:`zupt_ekf`, :mod:`compiled_filter`, :mod:`compiled_smoother`: the ZUPT/ZARU
  error-state EKF and the RTS smoother (Simón Colomar et al. 2012, Eqs. (6)–(9), Alg. 1;
  Wang et al. 2020, Eq. (2)); :mod:`kernel_data`: the named rows, state, parameters and
  samples (NamedTuples) their compiled kernels pass.
- :mod:`config`: the YAML configuration; :mod:`offline`: whole bags;
  :mod:`foot_offline`: ``pdr-ekf run``, its Python entry point
  (:func:`foot_offline.run`) and its steps; :mod:`streaming`: sample by sample;
  :mod:`nodes.zupt_ekf`: the ROS node.
- :mod:`cli`: ``pdr-ekf``; :mod:`plots`: its figures.

Research tooling (Monte-Carlo, closed-form error model, sweeps) lives in
:mod:`pdr_ins_ekf.studies`, which imports the navigator and never the reverse.
"""
