"""The config files' schemas (pydantic): a suspension file (:mod:`.suspension`), its axle
section (:mod:`.axle`), flexible beams (:mod:`.beam`), the joints-from-motion plan
(:mod:`.motion`), rig files (:mod:`.rig`), vehicle files (:mod:`.vehicle`) and the shared
field types (:mod:`.base`). Units: mm, N, N*mm, deg, as every file states."""
