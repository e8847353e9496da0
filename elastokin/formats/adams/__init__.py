"""ADAMS/Car files: the TeimOrbit reader and ADAMS unit names (:mod:`.teimorbit`,
:mod:`.teimorbit_units`), hardpoint tables and property files (bushings, springs, curves),
subsystems and assemblies, the database's confined paths (:mod:`.database`), import into a
config (:mod:`.importing`, :mod:`.mapping`) and export from one (:mod:`.export`), and the K&C
CSV in ADAMS/Car's frame (:mod:`.kc`). Units: elastokin's (mm, N, N*mm, deg), converted from
each file's ``[UNITS]`` block on reading."""
