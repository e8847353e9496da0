"""File formats at the boundary: CMM point files (IGES, CSV), K&C rig test files, ADAMS/Car
files, config YAML writing. Units are converted here, once.
"""
