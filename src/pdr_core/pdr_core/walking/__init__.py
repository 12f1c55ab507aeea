"""What a person's walk can be, and whether a navigator's input looks like one.

Modules:
    gait               What a person can walk: the stride bound at a cadence, the walking
                       speed limit.
    stair_geometry     What a staircase can be: the building codes' risers and flights
                       (SI units).
    walk_plausibility  Whether a navigator's input looks like a walk (the first line's
                       warnings, --strict), EXIT_REFUSED.
    navigator_choice   The foot or the pocket navigator, told from the IMU alone.
"""
