"""The paper's figures and tables, one module each, declared as studies: ``runs``, ``measure``, ``plot`` and
``claims`` (``fig2``: ``run`` instead of ``runs`` and ``measure``).

:data:`neurowalk.experiments.FIGURES` names them (figure name, title, module); ``neurowalk figure NAME`` runs one.
"""
