"""Foot-mounted strapdown INS (papers 000, 001, 004).

In place: attitude increments of 000 section III-A (:mod:`attitude_update`), pure-INS
mechanization (:mod:`strapdown`), and the mechanization study of 000 Fig. 6
(:mod:`mechanization_study`, ``pdr-ekf study mechanization``). The zero-velocity
detectors, the ZUPT/ZARU error-state EKF and the ``zupt_ekf`` node land with their issue.
"""
