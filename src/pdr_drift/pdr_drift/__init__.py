"""Landmark detection, revisit recognition and heading-drift corrections.

The package is registered in the workspace so that the graph and the build are in place;
its algorithms land with the drift estimation issue.
"""
