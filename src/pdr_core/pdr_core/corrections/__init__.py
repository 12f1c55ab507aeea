"""Drift corrections, from their sender to a navigator's filter, late ones included.

Modules:
    correction         A drift correction as one value, sender to filter.
    answered_requests  A request sent again answered as the first time: the navigators'
                       answers by request id, the sender's new ids.
    checkpoints        A navigator's state kept at past instants with the inputs since
                       (robot_localization's revertTo).
    replay             One replay for the corrections that come late, for any navigator: a
                       correction taken at its instant and the inputs run again.
"""
