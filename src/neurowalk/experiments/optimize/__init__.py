"""``neurowalk optimize``: CMA-ES over the sensory network's learning parameters (:mod:`.search`), its search
space and fitness rule (:mod:`.space`), and what it reports (:mod:`.report`)."""
