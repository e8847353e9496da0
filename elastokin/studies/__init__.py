"""Studies: the K&C job as a chain of named steps, models against test data, tolerance /
DOE studies (the only package that imports dask).
"""
