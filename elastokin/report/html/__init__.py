"""The HTML reports (a sub-package): the K&C run's ``report.html`` (:mod:`.page`) with its
Axle, Loads and Joints-from-motion sections (:mod:`.axle`, :mod:`.loads`, :mod:`.motion`),
the whole car's (:mod:`.vehicle`), and the pieces they are made of (:mod:`.parts`: escaped
text, numbers, tables, notes). Units as in the files they read (mm, N, N*mm, deg)."""
