"""Foot-mounted strapdown INS with ZUPT/ZARU error-state Kalman filter (issues 4-6).

The package is registered in the workspace so that the graph and the build are in place;
its algorithms land with the pdr_ins_ekf issues.
"""
