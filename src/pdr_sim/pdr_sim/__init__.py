"""IMU simulator of a foot and a thigh (trouser pocket), bag playback and recording, and
the ``pdr-sim`` CLI.

Data flow: scenario -> trajectory (the truth) -> true signals (:mod:`signals`) -> sensor
errors (:mod:`pdr_core.sensors.imu_errors`) -> message batches (:mod:`simulation`) -> bag
(``pdr-sim generate``) or the live graph (:mod:`nodes.imu_sim`).

- :mod:`scenario`: foot scenarios, segments of standing, walking, curves, turns and the
  gaits; built-in ones in ``scenarios/*.yaml`` (pocket ones in ``scenarios/pocket/``);
  :mod:`overrides`: ``KEY=VALUE`` overrides of their YAML (``--set``, ``--imu-set``).
- :mod:`trajectory`: a sampled trajectory of a body-mounted IMU, the ground truth.
- :mod:`foot_trajectory`: the foot's trajectory (Zampella et al. 2011, section II), from
  the step patterns of :mod:`step_pattern` (Eqs. (1)–(2)) and, for running, stairs,
  stepping in place, side and back steps and crawling, the gaits of :mod:`foot_gaits`
  built from the pieces of :mod:`foot_pieces`.
- :mod:`pocket_scenario`: pocket scenarios (who walks, where the phone sits, the route);
  :mod:`gait_plan`: their gait cycles and rests; :mod:`thigh_trajectory`: the thigh's
  trajectory and truth (steps, activities, landmarks), with :mod:`compiled_thigh` its
  per-sample kinematics (numba); :mod:`paired_foot`: the foot of the pocket's leg on the
  same walk (``--with-foot``), a second IMU for one pedestrian.
- :mod:`signals`: specific force, angular rate and magnetic field of any trajectory.
- :mod:`simulation`: a scenario and an IMU profile to the messages of a run.
- :mod:`step_fit`: step patterns fitted to a recorded foot (Zampella et al. 2011,
  Eqs. (3)–(5)).
- :mod:`allan_report`: ``pdr-sim allan``; :mod:`plots`: the figures; :mod:`cli`:
  ``pdr-sim``.
- :mod:`nodes`: ``bag_play``, ``bag_record`` and ``imu_sim``.
"""
