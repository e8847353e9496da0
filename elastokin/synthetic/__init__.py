"""Synthetic case-study data: the virtual CMM and the synthetic "real" suspension whose rig
runs become the K&C test files.
"""
