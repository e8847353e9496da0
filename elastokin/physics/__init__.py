"""Pure numpy physics and geometry: bushing laws, wheel angles (toe, camber), steering
geometry (caster, kingpin inclination, scrub, trail, screw axis), the reference paper's pose
and frame equations, plain state types. Imports nothing of elastokin but :mod:`elastokin.errors`.
"""
