"""Studies of the pocket navigator, run on purpose (``pdr-pocket tables``,
``pdr-pocket calibrate-step``); the navigator never imports them.

- :mod:`.tables`: the thesis' comparison tables on simulated bags (Muñoz Díaz 2016,
  Tables 4.1 and 4.4) and the stride calibration.
"""
