"""The paper's figures and tables, one module each: ``run(*, quick, seed, ...) -> Result`` and ``plot(result)``.

:data:`neurowalk.experiments.FIGURES` names them (figure name, title, module); ``neurowalk figure NAME`` runs one.
"""
