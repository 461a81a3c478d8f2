"""The paper's figures and tables, one module each: ``run(settings) -> Result`` and ``plot(result)``.

:data:`neurowalk.experiments.FIGURES` names them (figure name, title, module); ``neurowalk figure NAME`` runs one.
"""
