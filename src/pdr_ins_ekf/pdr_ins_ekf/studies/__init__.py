"""Research tooling of the foot INS: the papers' error analyses, built on the navigator.

- :mod:`.montecarlo`: pure-INS Monte-Carlo error growth (Zampella et al. 2011,
  Eqs. (13)–(14), Table I).
- :mod:`.ekf_montecarlo`: the ZUPT EKF batched over runs (Zampella et al. 2011,
  Tables II–III), NEES.
- :mod:`.zupt_error_model`: the closed-form ZUPT error levels (Wang et al. 2020,
  Eqs. (38)–(57)).
- :mod:`.error_sweep`: that model against the EKF over ARW, VRW, RRW (Wang et al. 2020,
  Figs. 3–6).
- :mod:`.mechanization_study`: attitude methods against sample rate (Zampella et al.
  2011, Fig. 6).
- :mod:`.cli`, :mod:`.montecarlo_cli`, :mod:`.analytic_cli`: their ``pdr-ekf`` subcommands.
- :mod:`.plots`: their figures.

The studies import the navigator; the navigator never imports them.
"""
