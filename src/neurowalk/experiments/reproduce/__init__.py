"""``neurowalk reproduce``: every result of the paper measured, judged against the paper, and reported.

* :mod:`.plan`: the results (:data:`~.plan.PLAN`), each with the figure command that measures it; its judge is the
  figure's own ``claims`` (in its module, beside its measure), which read its saved numbers and give the paper's
  results as claims; :mod:`.claims` holds the rules of their verdicts.
* :mod:`.runner`: runs the figure commands (resumable) and writes each result's ``NAME.json``;
  :mod:`.report`: ``report.md``; :mod:`.timing`: the committed run's times (``figure list``, progress).
"""
