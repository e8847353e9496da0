"""The multibody layer, the only package that imports Exudyn: model build, design state,
assembly check, user functions, ball-joint friction, static solves along a path.
"""
