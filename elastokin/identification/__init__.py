"""Identification: the reference paper's geometric identification from CMM data (no solver
imports) and the bushing-stiffness fit to K&C test data.
"""
