"""``neurowalk calibrate``: a physics body measured (:mod:`.physics`) and fitted (:mod:`.fit`) so that a planar
surrogate moves like it."""
