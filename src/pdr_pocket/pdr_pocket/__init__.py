"""Step-and-heading navigation for a trouser-pocket IMU.

The package is registered in the workspace so that the graph and the build are in place;
its algorithms land with the pocket navigation issue.
"""
