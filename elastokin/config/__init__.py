"""The config layer: the YAML schema (pydantic), the resolved frozen
:class:`~elastokin.config.suspension.Suspension`, loaders of config and rig files, and model
variants as typed overrides.
"""
