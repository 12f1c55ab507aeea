"""IMU simulation, bag playback and recording, and the ``pdr-sim`` CLI."""
