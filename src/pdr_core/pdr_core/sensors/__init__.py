"""IMU, magnetometer and barometer data: checked, modelled, calibrated and paired.

Modules:
    imu_checks                The checks every navigator runs on IMU data, and the CSV
                              importer's unit checks.
    imu_errors                Sensor error models applied to whole signals and runs.
    imu_profiles              Named IMU profiles and their configuration keys.
    allan                     Overlapping Allan deviation and the noise parameters on it.
    magnetic_field            Homogeneous and cylinder-perturbed fields, iron distortion.
    magnetometer_calibration  Hard/soft-iron calibration by ellipsoid fitting.
    magnetometer_pairing      Each IMU sample paired with its latest magnetometer reading.
    sample_pairing            A slow sensor's readings on the IMU's samples, each once; a
                              faster sensor's mean over each sample's interval.
    atmosphere                Pressure and height: the standard atmosphere's formula.
    barometry                 The barometer's limits and the kinds of height change.
"""
