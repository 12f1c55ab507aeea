"""Research tooling of the foot INS: the papers' error analyses, built on the navigator.

- :mod:`.montecarlo`: pure-INS Monte-Carlo error growth (000, Eqs. (13)–(14), Table I).
- :mod:`.ekf_montecarlo`: the ZUPT EKF batched over runs (000, Tables II–III), NEES.
- :mod:`.zupt_error_model`: the closed-form ZUPT error levels (004, Eqs. (38)–(57)).
- :mod:`.error_sweep`: that model against the EKF over ARW, VRW, RRW (004, Figs. 3–6).
- :mod:`.mechanization_study`: attitude methods against sample rate (000, Fig. 6).
- :mod:`.cli`, :mod:`.montecarlo_cli`, :mod:`.analytic_cli`: their ``pdr-ekf`` subcommands.
- :mod:`.plots`: their figures.

The studies import the navigator; the navigator never imports them.
"""
