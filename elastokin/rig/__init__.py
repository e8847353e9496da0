"""The virtual K&C rig: load cases as drivers attached to a built model (pad, loads, recorded
channels), sweeps, characteristics, gradients, compliance matrix and the one channel table.
"""
