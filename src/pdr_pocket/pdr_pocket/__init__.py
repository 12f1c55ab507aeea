"""Step-and-heading navigation for an IMU in the trouser pocket (Muñoz Díaz 2016).

The navigator (chapters 3, 4 and 6):

- :mod:`orientation`: the orientation filter, a UKF with gyro bias states, bulk and sample
  by sample, with external yaw and z-bias corrections (chapter 3, Eq. (6.2));
  :mod:`compiled_orientation`: its per-sample loop (numba).
- :mod:`magnetometer`: hard/soft-iron calibration and sphere coverage (Section 3.4.4).
- :mod:`compiled_mounting`: the thigh's frame in the sensor's, the thigh pitch and
  heading, learned sample by sample (numba).
- :mod:`steps`: the step detectors (Section 4.1); :mod:`compiled_peaks`: their per-sample
  loops, the pitch maxima and the footfalls (numba); :mod:`lowpass_design`: the footfalls'
  Butterworth low-pass, designed as scipy.signal does without importing it;
  :mod:`compiled_biquads`: that low-pass, run (numba).
- :mod:`activity`: a step's activity from the thigh pitch (Section 4.1.3), standing or
  sitting at rest.
- :mod:`step_length`: the stride models behind one interface and their calibration
  (Section 4.2); :mod:`stairs`: vertical displacement on stairs and floors (Section 4.3).
- :mod:`position`: the position filter, with heading and heading drift (chapter 6).
- :mod:`line_calibration`: the person's own stride and riser lines (Eqs. (4.2), (4.4),
  (4.5)), learned from a foot INS's strides paired by stamp with the pocket's steps
  (Section 7.3); :mod:`saved_lines`: their saved fit.
- :mod:`navigator`: :class:`~navigator.PocketNavigator`, composing them per chunk of
  samples, the same whatever the chunks.
- :mod:`config`: the YAML configuration (``config/pocket_pdr.yaml``).

Around it:

- :mod:`streaming`: the live path, sample by sample; :mod:`nodes.pocket_pdr`: the node.
- :mod:`inputs`: a bag's inputs, cleaned and paired, for every offline tool;
  :mod:`messages`: the outputs as messages, shared by the node and the bag writer.
- :mod:`drift_loop`: the navigator with the landmark drift corrections of pdr_drift in
  one process (``--drift online|offline``, Sections 6.1–6.2).
- :mod:`pocket_offline`: ``pdr-pocket run`` on a whole bag; :mod:`run_report`: its report
  and the attitude report of ``pdr-pocket attitude``, against a truth when there is one;
  :mod:`evaluation`: ``pdr-pocket evaluate``, a run's report against a truth given later.
- :mod:`studies`: the thesis' comparison tables on simulated bags (Tables 4.1 and 4.4)
  and ``pdr-pocket calibrate-step``. The navigator imports none of the report, evaluation
  or study modules (test/test_code_shape.py).
- :mod:`cli`: ``pdr-pocket``; :mod:`plots`: its figures.
"""
